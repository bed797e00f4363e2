# Shared by the tracking tests (sourced after check_lib.sh): `expect NAME EXIT_CODE REGEX -- command...` runs the
# command into $T/out and records ok when it exits EXIT_CODE and its output matches the extended REGEX.
expect() {
  local name=$1 code=$2 re=$3; shift 4
  "$@" >"$T/out" 2>&1
  local got=$?
  if [ "$got" -ne "$code" ]; then fail "$name: exit $got, expected $code: $(tail -c 800 "$T/out")"; return; fi
  if ! grep -Eq -- "$re" "$T/out"; then fail "$name: output does not match /$re/: $(tail -c 800 "$T/out")"; return; fi
  ok "$name"
}
