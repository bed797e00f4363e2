#!/usr/bin/env bash
# The static result site (python/dbtools/site) in a real browser: generated from a small fixture (tests/site_fixture.py:
# four reports and their figures, a thread-scaling folder, one case of the frames study's meshes; two tracking
# histories of tests/track_fake_measure.py), every page opened in headless Chromium (tests/site_browser.py, the DevTools
# protocol): no console error, no uncaught exception, no resource that fails to load, no broken link, and the
# viewer's canvas drawn (a screenshot with many colours). Then the checker must bite: a page with a missing image,
# a console.error and an uncaught exception fails, naming each. Skipped (exit 77) only where Chromium is not
# installed.
#   site_test.sh SOURCE_DIR      (SITE_TEST_SHOTS=DIR keeps the screenshots)
set -u
SRC=$(cd "$1" && pwd)
if ! command -v chromium >/dev/null; then
  echo "SKIP: chromium is not installed (Debian's chromium; ./run test installs it):" \
    "the site is not tested in a browser"
  exit 77
fi
. "$(dirname "$0")/check_lib.sh"  # $T, fail, ok, $fails
export PYTHONPATH=$SRC/python PYTHONDONTWRITEBYTECODE=1
R=$T/results
/usr/bin/python3 "$SRC/tests/site_fixture.py" "$R" || { echo "FAIL the fixture"; exit 1; }

# Two runs of the tracking suite's stand-in on one machine, of two commits.
for k in 1 2; do
  mkdir -p "$T/src$k" "$R/history/runs"
  printf 'nnz_factor=%s\nfactorize_s=%s\n' $((1000 * k)) "0.$k" >"$T/src$k/measure.txt"
  DEFORMBENCH_GIT_SHA=abc$k /usr/bin/python3 "$SRC/tests/track_fake_measure.py" measure "$T/src$k" \
    "$R/history/runs/2026112${k}T000000Z_abc${k}_fake-machine.csv" "abc${k}000000000" || fail "history $k"
done

# An unreadable mesh costs its case only, named.
printf 'ply\nnot a mesh\n' >"$R/meshes/frames/broken__rest.ply"
/usr/bin/python3 -m dbtools.site --results "$R" >"$T/out" 2>&1 && ok "site generated" || fail "site: $(cat "$T/out")"
grep -q "viewer: case broken left out: .*broken__rest.ply: not a PLY file" "$T/out" &&
  ok "a broken mesh named, left out" ||
  fail "broken mesh: $(cat "$T/out")"
S=$R/site
for f in index.html table_2_1.html solvers.html frames.html applications.html threads.html history.html \
  history_factorize_s.html history_nnz_factor.html viewer.html viewer.js style.css meshes/index.js \
  meshes/tiny_cactus.js three/three.min.js three/OrbitControls.js; do
  [ -s "$S/$f" ] || fail "no $f"
done
for p in table_2_1 solvers frames applications threads history viewer; do
  grep -q "href=\"$p.html\"" "$S/index.html" || fail "index.html does not link $p.html"
done
grep -q 'href="frames.html"' "$S/table_2_1.html" && grep -q 'src="../figures/table_2_1_init.png"' "$S/table_2_1.html" &&
  ok "a report's links and figures" || fail "table_2_1.html: $(cat "$S/table_2_1.html")"
grep -q 'src="../threads/threads.png"' "$S/threads.html" && grep -q "bar (6k)" "$S/threads.html" &&
  ok "the thread-scaling folder's page: its table and figure" || fail "threads.html: $(cat "$S/threads.html")"
grep -q '"configs": \["rest", "LAP", "TF", "TF, scale-free", "LRI"\]' "$S/meshes/index.js" &&
  ok "the viewer's case: rest, LAP, TF, scale-free TF, LRI" || fail "meshes/index.js: $(cat "$S/meshes/index.js")"
grep -q "abc1" "$S/history_factorize_s.html" && grep -q "abc2" "$S/history_factorize_s.html" &&
  ok "history: both commits" || fail "history_factorize_s.html lacks a commit"

SHOTS=${SITE_TEST_SHOTS:-$T/shots}
mkdir -p "$SHOTS"
B=(/usr/bin/python3 "$SRC/tests/site_browser.py")
"${B[@]}" "$S" --screenshot "$SHOTS/viewer_canvas.png" --page-shots "$SHOTS" >"$T/out" 2>&1
rc=$?
cat "$T/out"
[ $rc -eq 0 ] && ok "every page clean in Chromium, the viewer drawn" || fail "site_browser: exit $rc"
grep -Eq "^ok +viewer.html \(canvas [0-9]+x[0-9]+: [0-9]+ colours.*clicked through: 6/1" "$T/out" &&
  ok "viewer canvas checked" ||
  fail "the viewer's canvas was not checked"

# The checker bites: a page with a missing image, a console.error and an uncaught exception.
cp -r "$S" "$T/bad"
cat >"$T/bad/bad.html" <<'HTML'
<!doctype html><html><head><title>bad</title></head><body><img src="missing.png">
<script>console.error("planted error");</script><script>undefinedFunction();</script></body></html>
HTML
"${B[@]}" "$T/bad" >"$T/out" 2>&1
rc=$?
[ $rc -eq 1 ] && ok "a bad page fails" || fail "bad page: exit $rc: $(cat "$T/out")"
for re in "broken link: bad.html: missing.png" "bad.html: console.error: planted error" \
  "bad.html: uncaught: ReferenceError: undefinedFunction" "bad.html: log error: Failed to load resource"; do
  grep -q "FAIL $re" "$T/out" && ok "names: $re" || fail "not named: $re: $(cat "$T/out")"
done

if ((fails)); then echo "$fails failure(s)"; exit 1; fi
echo "all passed"
