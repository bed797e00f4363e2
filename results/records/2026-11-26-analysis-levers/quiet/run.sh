#!/usr/bin/env bash
# The quiet run of this record: 2026-11-26-analysis-2core-quiet's script, unchanged, writing its CSVs and table.md
# here. usage (from the repository root): results/records/2026-11-26-analysis-levers/quiet/run.sh ROUNDS [PART]
here=$(cd "$(dirname "$0")" && pwd)
RECORD_DIR=$here exec bash "$here/../../2026-11-26-analysis-2core-quiet/run.sh" "$@"
