#!/usr/bin/env bash
# Where the TF init's serial passes go at 16 and 8 threads on the device: the head with PROBE prints
# (probe.patch beside this script in the record), two runs each of the 104k and 416k TF edits, into $OUT/probe.txt
# (the PROBE lines, then each run's deform row after CSV).
set -u
D=$PWD/.device
if [ -d "$D/lib" ]; then
  for l in libblas.so.3 liblapack.so.3; do ldconfig -p | grep -q "$l " || cp "$D/fallback/$l" "$D/lib/"; done
  export LD_LIBRARY_PATH=$D/lib
fi
W=$(mktemp -d); cd "$W"
gunzip -c "$D/armadillo_loop1.off.gz" > armadillo_loop1.off
"$D/bin/meshtool" subdivide armadillo_loop1.off armadillo_loop2.off 1 > /dev/null 2>&1
for k in 1 2; do
  printf 'name = armadillo_loop%s_whole\nmesh = armadillo_loop%s.off\nroi = all\nhandle = nearest:-20.2599,97.1076,-28.8554,100\ntransform = translate:0,10,0\n' $k $k > e$k.edit
done
for i in 1 2; do for k in 1 2; do for T in 16 8; do
  echo "# e$k T=$T run $i" >> "$OUT/probe.txt"
  DEFORMBENCH_THREADS=$T OPENBLAS_NUM_THREADS=$T OMP_NUM_THREADS=$T timeout 60 "$D/bin/deformbench_probe" deform e$k.edit \
    --method tf --constraints soft --frames 1 --out o.ply --csv o.csv 2>&1 >/dev/null | grep PROBE >> "$OUT/probe.txt"
  [ -n "${header:-}" ] || { header=1; head -1 o.csv | sed 's/^/CSV /' >> "$OUT/probe.txt"; }
  tail -n 1 o.csv | sed 's/^/CSV /' >> "$OUT/probe.txt"
done; done; done
rm -rf "$W"
