#!/bin/bash
# usage: bench/rounds/replaced.sh OUT
# Exit status 0 when bench/results/OUT.json (bench/select_policy.py's rule with its confirmation draws) says its
# candidate replaces the baseline; 1 otherwise, a missing or unreadable file included.
cd "$(dirname "$0")/../.."
.venv/bin/python -c "import json, sys; sys.exit(not json.load(open(sys.argv[1]))['replaces_baseline'])" \
  "bench/results/$1.json" 2> /dev/null
