#!/usr/bin/env bash
# bench_lio_scenes: LiDAR-inertial odometry (`ultrafusion run`, auto mode = LIO) on simulated 60 s sequences
# of the given scenes (default: urban, tunnel, corridor; 32-beam LiDAR + IMU, no camera/wheel/GNSS), with the
# ATE against the simulator's ground truth (SE3-aligned, and aligned by yaw and translation only, where a tilt
# of the gravity-aligned world counts) and the time per scan, as `ultrafusion run` reports them.
#   usage: bench/bench_lio_scenes.sh [--duration S] [--keep DIR] [SCENE ...]
# The tunnel and the corridor are LiDAR-degenerate along their axis: their figures are reported, not targets.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
keep=""
scenes=()
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
((${#scenes[@]})) || scenes=(urban tunnel corridor)
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
echo "bench_lio_scenes: ${duration} s per scene, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-10s %10s %10s %10s %10s %8s %s\n' scene ATE_m yaw_ATE_m ms_mean ms_p95 warn init
for scene in "${scenes[@]}"; do
  rm -rf "$work/$scene" "$work/$scene-run"
  "$bin" sim --scene "$scene" --duration "$duration" --no-camera --no-wheel --no-gnss --out "$work/$scene" >/dev/null 2>&1
  "$bin" run "$work/$scene" --config "$root/configs/run-sim.yaml" --no-map --out "$work/$scene-run" >"$work/$scene.log" 2>&1 ||
    { echo "$scene: run failed, see $work/$scene.log"; continue; }
  ate=$(sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$work/$scene.log")
  yaw=$(sed -n 's/.*ATE (yaw-aligned RMSE, a tilt counts): \([0-9.]*\) m.*/\1/p' "$work/$scene.log")
  mean=$(sed -n 's/.*"mean": *\([0-9.]*\).*/\1/p' "$work/$scene-run/timing.json" | head -1)
  p95=$(sed -n 's/.*"p95": *\([0-9.]*\).*/\1/p' "$work/$scene-run/timing.json" | head -1)
  warnings=$(sed -n 's/.*"warnings": *\([0-9]*\).*/\1/p' "$work/$scene-run/timing.json" | head -1)
  init=$(sed -n 's/.*LIO initialized: \([A-Z] ([a-z-]*) after [0-9.]* s\).*/\1/p' "$work/$scene-run/report.md" | head -1)
  printf '%-10s %10s %10s %10s %10s %8s %s\n' "$scene" "$ate" "${yaw:--}" "$mean" "$p95" "$warnings" \
    "${init:-never}"
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
