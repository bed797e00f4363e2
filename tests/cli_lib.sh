# Shared by the command-line tests (sourced after BIN is set): a temporary directory $T removed on exit, the
# counters, `expect` and a small OFF mesh.
set -u
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
fails=0; passes=0

# expect NAME EXIT_CODE MESSAGE_REGEX -- args...: runs $BIN args and checks the exit code; the message (stderr for
# a failure, stdout and stderr for success; lines joined) against the regex; for a failure, that no $T/out.* (nor
# its temporary) is left behind and that it came within seconds (refusals are decided before any real work).
expect() {
  local name=$1 code=$2 re=$3; shift 4
  rm -f "$T"/out.*
  local t0 got ms ok=1
  t0=$(date +%s%N)
  timeout 120 "$BIN" "$@" >"$T/stdout" 2>"$T/stderr"
  got=$? ms=$((($(date +%s%N) - t0) / 1000000))
  if [ "$code" -eq 0 ]; then cat "$T/stdout" "$T/stderr" >"$T/message"; else cp "$T/stderr" "$T/message"; fi
  [ "$got" -eq "$code" ] || { echo "FAIL $name: exit $got, expected $code"; ok=0; }
  tr '\n' ' ' <"$T/message" | grep -Eqi -- "$re" || { echo "FAIL $name: message does not match /$re/:"; cat "$T/message"; ok=0; }
  if [ "$code" -ne 0 ] && ls "$T"/out.* >/dev/null 2>&1; then echo "FAIL $name: output file left behind"; ok=0; fi
  if [ "$code" -ne 0 ] && [ "$ms" -gt 10000 ]; then echo "FAIL $name: took $ms ms"; ok=0; fi
  if ((ok)); then passes=$((passes + 1)); echo "ok   $name: $(head -c 200 "$T/message" | tr '\n' ' ')"; else fails=$((fails + 1)); fi
}

# A small valid closed mesh: an octahedron (6 vertices, 8 faces).
octa_v='1 0 0
-1 0 0
0 1 0
0 -1 0
0 0 1
0 0 -1'
octa_f='3 0 2 4
3 2 1 4
3 1 3 4
3 3 0 4
3 2 0 5
3 1 2 5
3 3 1 5
3 0 3 5'
write_off() { # file nv nf vertices faces
  printf 'OFF\n%s %s 0\n%s\n%s\n' "$2" "$3" "$4" "$5" >"$1"
}
