#!/usr/bin/env bash
# bench_lvio: LiDAR-visual-inertial odometry (`ultrafusion run --mode lvio`) against LIO on the same
# simulated drives (the default 32-beam LiDAR, the IMU and the forward 640 x 480 camera; no wheel or GNSS),
# with configs/run-sim.yaml, for the given scenes and seeds (default urban and corridor, seeds 1 2 3, 60 s).
# Prints per sequence the ATE of both against the simulator's ground truth, their ratio, the time per scan
# (the window) and per frame (the visual front end), and the mean ratio per scene, with the load average
# (2 shared cores).
#   usage: bench/bench_lvio.sh [--duration S] [--scenes "urban corridor"] [--seeds "1 2 3"] [--delay S]
#                              [--keep DIR]
# --delay S: the camera stamps run S late (sim --camera-stamp-delay) and LVIO estimates t_d
# (lio.visual.estimate_time_offset); the table adds the estimate (the truth is -S).
# --keep DIR keeps the sequences and runs there, and reuses the sequences found there on the next call.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
scenes="urban corridor"
seeds="1 2 3"
delay=""
keep=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --delay) delay="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) echo "bench_lvio: unknown argument $1" >&2; exit 2 ;;
  esac
done
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
run_config="$work/run.yaml"
cp "$root/configs/run-sim.yaml" "$run_config"
# run-sim.yaml's lio: has a visual: section (before wio:'s): the key goes into the first.
[[ -z "$delay" ]] || sed -i '0,/^  visual:$/s//  visual:\n    estimate_time_offset: true/' "$run_config"
echo "bench_lvio: ${duration} s, scenes $scenes, seeds $seeds${delay:+, camera delay $delay s}, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-9s %4s %9s %9s %6s %11s %11s %12s %9s\n' scene seed LIO_ATE_m LVIO_ATE_m ratio LIO_ms/scan \
  LVIO_ms/scan front_ms/frame t_d_s
# ATE (m) of RUN against DATA's ground truth, and its mean ms/scan.
figures() {
  "$bin" eval "$1/groundtruth.tum" "$2/trajectory.tum" 2>/dev/null | awk '/^APE/ { printf "%s ", $3 }'
  sed -n 's/.* \([0-9.]*\) ms\/scan mean.*/\1/p' "$2.log" | head -1
}
for scene in $scenes; do
  sum_ratio=0 n=0
  for seed in $seeds; do
    data="$work/$scene-$seed-${duration}s${delay:+-d$delay}"
    if [[ ! -f "$data/dataset.yaml" ]]; then
      rm -rf "$data"
      "$bin" sim --scene "$scene" --seed "$seed" --duration "$duration" --no-wheel --no-gnss \
        ${delay:+--camera-stamp-delay "$delay"} --out "$data" >"$data.sim.log" 2>&1 ||
        { echo "$scene $seed: sim failed, see $data.sim.log"; continue; }
    fi
    for mode in lio lvio; do
      rm -rf "$data-$mode"
      "$bin" run "$data" --config "$run_config" --mode "$mode" --no-map --out "$data-$mode" >"$data-$mode.log" 2>&1 ||
        { echo "$scene $seed: $mode failed, see $data-$mode.log"; continue 2; }
    done
    read -r lio_ate lio_ms < <(figures "$data" "$data-lio")
    read -r lvio_ate lvio_ms < <(figures "$data" "$data-lvio")
    front=$(awk -F, 'NR > 1 { s += $16; n++ } END { if (n) printf "%.1f", s / n }' "$data-lvio/tracks.csv")
    td=$(sed -n 's/.*camera time offset t_d \(-*[0-9.]*\) s.*/\1/p' "$data-lvio/report.md" | head -1)
    ratio=$(awk -v a="$lvio_ate" -v b="$lio_ate" 'BEGIN { printf "%.3f", a / b }')
    printf '%-9s %4s %9s %9s %6s %11s %11s %12s %9s\n' "$scene" "$seed" "$lio_ate" "$lvio_ate" "$ratio" \
      "$lio_ms" "$lvio_ms" "${front:--}" "${delay:+$td}"
    read -r sum_ratio n < <(awk -v a="$sum_ratio" -v c="$n" -v x="$ratio" 'BEGIN { print a + x, c + 1 }')
  done
  ((n)) && awk -v s="$scene" -v a="$sum_ratio" -v n="$n" \
    'BEGIN { printf "%-9s %4s %9s %9s %6.3f   (mean ratio of %d)\n", s, "mean", "", "", a / n, n }'
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
