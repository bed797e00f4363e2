#!/usr/bin/env bash
# docs/cli.md lists deform's options exactly as the options table does (`deformbench deform-options`): the listing
# between its BEGIN/END deform-options markers is that command's output. On a difference it prints the diff and
# how to regenerate the block.
#
#   tests/docs_options_test.sh PATH/TO/deformbench SOURCE_DIR [--write]   (--write: put the listing in the doc)
set -euo pipefail
BIN=$1
DOC=$2/docs/cli.md
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
"$BIN" deform-options >"$T/generated.md"
if [[ ${3:-} == --write ]]; then
  awk -v gen="$T/generated.md" '/^<!-- END deform-options/ { while ((getline l < gen) > 0) print l; skip = 0 }
    !skip { print } /^<!-- BEGIN deform-options/ { skip = 1 }' "$DOC" >"$T/doc.md"
  cat "$T/doc.md" >"$DOC"
fi
sed -n '/^<!-- BEGIN deform-options/,/^<!-- END deform-options/p' "$DOC" | sed '1d;$d' >"$T/documented.md"
[[ -s $T/generated.md ]] || { echo "FAIL: deformbench deform-options printed nothing"; exit 1; }
if ! diff -u "$T/documented.md" "$T/generated.md"; then
  echo "FAIL: docs/cli.md's option list differs from the options table; regenerate it with"
  echo "  tests/docs_options_test.sh build/deformbench . --write"
  exit 1
fi
echo "docs_deform_options: docs/cli.md lists the $(grep -c '^- `--' "$T/generated.md") options of the table"
