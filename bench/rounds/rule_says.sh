#!/bin/bash
# usage: bench/rounds/rule_says.sh OUT FIELD
# Exit status 0 when bench/results/OUT.json (a selection rule's file: bench/select_policy.py's or
# bench/select_denoiser.py's, or a round's own) holds FIELD true (e.g. leads_by_rule, replaces_baseline); 1 otherwise,
# a missing or unreadable file included.
cd "$(dirname "$0")/../.."
.venv/bin/python -c "import json, sys; sys.exit(not json.load(open(sys.argv[1]))[sys.argv[2]])" \
  "bench/results/$1.json" "$2" 2> /dev/null
