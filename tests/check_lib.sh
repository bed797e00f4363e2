# Shared by the shell tests (sourced): a scratch directory $T removed on exit, FAIL / ok lines counted in
# $fails (each test ends with its own verdict on $fails), and `value KEY FILE`: the first whole-word KEY=VALUE's
# value in FILE (the drivers' key=value report lines), and `expect NAME EXIT_CODE MESSAGE_REGEX -- command...`: the
# command's exit code and its stdout + stderr against the regex; it leaves them in $T/stdout, $T/stderr and both
# (stdout first) in $T/output.
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0
fail() { echo "FAIL $*"; fails=$((fails + 1)); }
ok() { echo "ok   $*"; }
value() { grep -o "\b$1=[^ ]*" "$2" | head -1 | cut -d= -f2; }

expect() {
  local name=$1 code=$2 re=$3; shift 4
  "$@" >"$T/stdout" 2>"$T/stderr"
  local got=$?
  cat "$T/stdout" "$T/stderr" >"$T/output"
  if [ "$got" -ne "$code" ]; then fail "$name: exit $got, expected $code: $(head -c 300 "$T/stderr")"; return; fi
  if ! grep -Eqi -- "$re" "$T/output"; then fail "$name: output does not match /$re/: $(tail -c 600 "$T/output")"; return; fi
  ok "$name"
}
