# Shared by the shell tests (sourced): a scratch directory $T removed on exit, FAIL / ok lines counted in
# $fails (each test ends with its own verdict on $fails), and `value KEY FILE`: the first whole-word KEY=VALUE's
# value in FILE (the drivers' key=value report lines).
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
ok() { echo "ok   $*"; }
value() { grep -o "\b$1=[^ ]*" "$2" | head -1 | cut -d= -f2; }
