# Shared by the shell tests (sourced): a scratch directory $T removed on exit, and FAIL / ok lines counted in
# $fails (each test ends with its own verdict on $fails).
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
ok() { echo "ok   $*"; }
