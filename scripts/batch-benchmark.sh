#!/usr/bin/env bash
# The batch figure of issue 16: a batch of N small synthetic trees (default
# 100) of which 10 are broken in ten different ways. Measures, in one run:
#   1. `sylva batch --jobs 1`, `--jobs 2` and the same trees one by one in a
#      shell loop (sylva init + sylva run): wall time of each;
#   2. that N - 10 trees finish with outputs and the 10 fail, each with the
#      reason expected of its breakage (summary.csv), and that no input file
#      changed;
#   3. a `--jobs 2` batch killed with kill -9 about halfway, then run again:
#      the re-run runs only the trees that had not finished.
# Everything happens in WORK (default /tmp/sylva-batch-benchmark, removed
# first); the figures are printed and written to WORK/figures.txt.
#   bash scripts/batch-benchmark.sh [N] [WORK]
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
N="${1:-100}"
WORK="${2:-/tmp/sylva-batch-benchmark}"
[ "$N" -ge 20 ] || { echo "N must be at least 20" >&2; exit 2; }
sylva_build sylva
sylva="$SYLVA_BUILD/bin/sylva"
rm -rf "$WORK"
mkdir -p "$WORK/data"
cd "$WORK"
# Small trees: a coarse grid, few particles and leaves, small previews.
fast=(--Density.resolution=48 --ParticleFlow.num_particles=300 --Leaves.num_leaves=500
  --Report.preview_size=64 --Attractors.write_overlays=false --log-level=warning)

sylva_log "Making 10 synthetic photo sets (4 + 1 held-out views, 96 px)"
for k in $(seq 1 10); do
  "$sylva" synth "data/set_$k" --seed "$k" --size 96 --samples 2 --views 4 --held-out 1 \
    --log-level warning > /dev/null 2>&1
done

# Ten broken copies, one breakage each: name, then what the error must say.
broken_names=(missing_photo corrupt_cameras wrong_format_cameras wrong_size_matte empty_matte
  not_an_image truncated_photo missing_matte bad_option_value unknown_held_out)
declare -A expected=(
  [missing_photo]="view_01.png"
  [corrupt_cameras]="cameras.json"
  [wrong_format_cameras]="cameras.json"
  [wrong_size_matte]="view_02.png"
  [empty_matte]="empty"
  [not_an_image]="view_00.png"
  [truncated_photo]="view_03.png"
  [missing_matte]="view_01.png"
  [bad_option_value]="Density.resolution"
  [unknown_held_out]="no_such_view.png")
for i in "${!broken_names[@]}"; do
  name="${broken_names[$i]}"
  cp -r "data/set_$((i % 10 + 1))" "data/$name"
done
rm data/missing_photo/photos/view_01.png
echo '{"format": "sylva-cameras", "cameras": [' > data/corrupt_cameras/cameras.json
echo '{"format": "something-else", "version": 1}' > data/wrong_format_cameras/cameras.json
convert data/wrong_size_matte/mattes/view_02.png -resize 50% data/wrong_size_matte/mattes/view_02.png
convert data/empty_matte/mattes/view_00.png -fill black -colorize 100 data/empty_matte/mattes/view_00.png
convert data/empty_matte/mattes/view_01.png -fill black -colorize 100 data/empty_matte/mattes/view_01.png
convert data/empty_matte/mattes/view_02.png -fill black -colorize 100 data/empty_matte/mattes/view_02.png
convert data/empty_matte/mattes/view_03.png -fill black -colorize 100 data/empty_matte/mattes/view_03.png
echo "this is not an image" > data/not_an_image/photos/view_00.png
head -c 300 "data/set_4/photos/view_03.png" > data/truncated_photo/photos/view_03.png
rm data/missing_matte/mattes/view_01.png
echo "no_such_view.png" > data/unknown_held_out/held_out.txt

sylva_log "Writing the manifest: $N trees, 10 of them broken"
{
  echo "name,photos,cameras,mattes,held_out,Density.resolution"
  for t in $(seq 1 $((N - 10))); do
    d="data/set_$(((t - 1) % 10 + 1))"
    printf 'tree_%03d,%s/photos,%s/cameras.json,%s/mattes,@%s/held_out.txt,\n' "$t" "$d" "$d" "$d" "$d"
  done
  for name in "${broken_names[@]}"; do
    d="data/$name"
    option=""
    if [ "$name" = bad_option_value ]; then option="abc"; fi
    printf '%s,%s/photos,%s/cameras.json,%s/mattes,@%s/held_out.txt,%s\n' "$name" "$d" "$d" "$d" "$d" "$option"
  done
} > manifest.csv
inputs_before=$(find data -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)

# Trees of batch folder $1 with a finished report (0 if there is no folder yet).
count_finished() { { find "$1" -maxdepth 3 -path '*/out/report.json' 2> /dev/null || true; } | wc -l; }
seconds() { python3 -c "import time; print(f'{time.monotonic():.3f}')"; }
elapsed() { python3 -c "print(f'{$2 - $1:.1f}')"; }

run_batch() {  # OUT JOBS
  local start end
  start=$(seconds)
  set +e
  "$sylva" batch manifest.csv "$1" --jobs "$2" "${fast[@]}" > "$1.stdout" 2> "$1.stderr"
  status=$?
  set -e
  end=$(seconds)
  echo "$(elapsed "$start" "$end") $status"
}

sylva_log "Batch with --jobs 1"
read -r t1 s1 <<< "$(run_batch out_jobs1 1)"
sylva_log "Batch with --jobs 2"
read -r t2 s2 <<< "$(run_batch out_jobs2 2)"

sylva_log "The same trees one by one in a shell loop (sylva init + sylva run)"
start=$(seconds)
loop_ok=0
tail -n +2 manifest.csv | while IFS=, read -r name photos cameras mattes held option; do
  project="out_loop/$name"
  extra=()
  if [ -n "$option" ]; then extra=(--Density.resolution="$option"); fi
  if "$sylva" init "$project" --photos "$photos" --cameras "$cameras" --mattes "$mattes" \
      --held-out "$held" --log-level error > /dev/null 2>&1 &&
    "$sylva" run "$project" "${fast[@]}" "${extra[@]}" > /dev/null 2>&1; then
    echo ok
  fi
done > loop_results.txt || true
end=$(seconds)
tloop=$(elapsed "$start" "$end")
loop_ok=$(grep -c ok loop_results.txt || true)

sylva_log "Killing a --jobs 2 batch with kill -9 about halfway, then running it again"
set +e
setsid "$sylva" batch manifest.csv out_killed --jobs 2 "${fast[@]}" > out_killed.first.stdout \
  2> out_killed.first.stderr &
batch_pid=$!
set -e
half=$(((N - 10) / 2))
while kill -0 "$batch_pid" 2> /dev/null; do
  finished=$(count_finished out_killed)
  if [ "$finished" -ge "$half" ]; then break; fi
  sleep 0.2
done
kill -9 -- "-$batch_pid" 2> /dev/null || true
wait "$batch_pid" 2> /dev/null || true
done_before=$(count_finished out_killed)
read -r tk sk <<< "$(run_batch out_killed 2)"
inputs_after=$(find data -type f -print0 | sort -z | xargs -0 sha256sum | sha256sum)

sylva_log "Checking the summaries"
python3 - "$N" "$t1" "$s1" "$t2" "$s2" "$tloop" "$loop_ok" "$done_before" "$tk" "$sk" \
  "$([ "$inputs_before" = "$inputs_after" ] && echo yes || echo no)" \
  "$(declare -p expected)" << 'EOF' | tee figures.txt
import csv, re, sys
(n, t1, s1, t2, s2, tloop, loop_ok, done_before, tk, sk, unchanged, expected_decl) = sys.argv[1:]
expected = dict(re.findall(r'\[(\w+)\]="([^"]*)"', expected_decl))
n = int(n)
ok_all = True

def check(out):
    global ok_all
    rows = {r["name"]: r for r in csv.DictReader(open(f"{out}/summary.csv"))}
    ok = [r for r in rows.values() if r["status"] in ("ok", "up-to-date")]
    failed = {k: r for k, r in rows.items() if r["status"] == "failed"}
    wrong = [k for k in expected if k not in failed or expected[k] not in failed[k]["error"]]
    extra = [k for k in failed if k not in expected]
    good = len(rows) == n and len(ok) == n - 10 and not wrong and not extra
    ok_all = ok_all and good
    return rows, ok, failed, wrong, extra, good

print(f"Batch of {n} trees ({n - 10} good, 10 broken), 4 + 1 views of 96 px each")
for out, t, s in (("out_jobs1", t1, s1), ("out_jobs2", t2, s2)):
    rows, ok, failed, wrong, extra, good = check(out)
    print(f"  {out}: {t} s wall, exit {s}; {len(ok)} finished, {len(failed)} failed; "
          f"wrong or missing reasons: {wrong or 'none'}; unexpected failures: {extra or 'none'}")
print(f"  shell loop: {tloop} s wall; {loop_ok} trees finished")
rows, ok, failed, wrong, extra, good = check("out_jobs2")
for name in expected:
    r = failed.get(name)
    print(f"    {name:22s} {r['stage'] if r else '-':9s} {(r['error'] if r else 'NOT FAILED')[:110]}")
# The re-run's own account ("Batch of N trees in Ts: A ran, B up to date, C
# failed"); summary.csv keeps each tree's status of the run that made it.
last = [l for l in open("out_killed.stdout") if l.startswith("Batch of")][-1]
ran, skipped = (int(x) for x in re.search(r"(\d+) ran, (\d+) up to date", last).groups())
print(f"  killed with kill -9 after {done_before} of {n - 10} good trees had finished; "
      f"the re-run took {tk} s (exit {sk}): {ran} trees run, {skipped} up to date")
print(f"  input files unchanged: {unchanged}")
ok_all = ok_all and unchanged == "yes" and skipped == int(done_before) and ran == n - 10 - int(done_before)
print("RESULT:", "all checks passed" if ok_all else "SOME CHECK FAILED")
sys.exit(0 if ok_all else 1)
EOF
