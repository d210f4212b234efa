#!/bin/bash
# usage: bench/rounds/replaced.sh OUT
# Exit status 0 when bench/results/OUT.json (bench/select_policy.py's rule with its confirmation draws) says its
# candidate replaces the baseline; 1 otherwise, a missing or unreadable file included (bench/rounds/rule_says.sh).
exec bash "$(dirname "$0")/rule_says.sh" "$1" replaces_baseline
