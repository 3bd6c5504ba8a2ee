#!/usr/bin/env bash
# bench_imu_deskew: LIO with the IMU's correction within the sweep off and on (lio.imu_deskew), on simulated
# sequences (32-beam LiDAR + IMU; no camera, wheel or GNSS) of the given scenes and seeds, plus one hand-held
# walk through `wild`. configs/run-sim.yaml with the solve budget lifted (lo.max_solver_time_s: 10) so that
# the figures repeat; ATE aligned in SE3 and by yaw only (a tilt counts), and the RPE per scan.
#   usage: bench/bench_imu_deskew.sh [--duration S] [--seeds "1 2"] [--keep DIR] [SCENE ...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=30
seeds="1 2"
keep=""
scenes=()
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
((${#scenes[@]})) || scenes=(urban wild corridor warehouse)
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
for deskew in false true; do
  sed -e 's/^  imu_deskew: false /  imu_deskew: '"$deskew"' /' -e 's/^lo:$/lo:\n  max_solver_time_s: 10/' \
    "$root/configs/run-sim.yaml" >"$work/deskew-$deskew.yaml"
  grep -q "^  imu_deskew: $deskew " "$work/deskew-$deskew.yaml" || { echo "configs/run-sim.yaml: no imu_deskew line"; exit 1; }
done

echo "bench_imu_deskew: ${duration} s, seeds $seeds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-18s %-8s %12s %12s %12s\n' case deskew ATE_se3_m ATE_yaw_m RPE_m
run_case() {  # name, sim arguments...
  local name="$1"; shift
  "$bin" sim "$@" --duration "$duration" --no-camera --no-wheel --no-gnss --out "$work/$name" >/dev/null 2>&1 ||
    { echo "$name: sim failed"; return; }
  for deskew in false true; do
    local out="$work/$name-$deskew"
    rm -rf "$out"
    "$bin" run "$work/$name" --config "$work/deskew-$deskew.yaml" --mode lio --no-map --out "$out" >"$out.log" 2>&1 ||
      { echo "$name: run failed, see $out.log"; continue; }
    local se3 yaw rpe
    se3=$(sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$out.log")
    yaw=$(sed -n 's/.*ATE (yaw-aligned RMSE, a tilt counts): \([0-9.]*\) m.*/\1/p' "$out.log")
    rpe=$("$bin" eval "$work/$name/groundtruth.tum" "$out/trajectory.tum" 2>/dev/null | awk '/^RPE/ {print $5}')
    printf '%-18s %-8s %12s %12s %12s\n' "$name" "$deskew" "$se3" "$yaw" "$rpe"
  done
}
for seed in $seeds; do
  for scene in "${scenes[@]}"; do run_case "$scene-s$seed" --scene "$scene" --seed "$seed"; done
done
run_case "wild-handheld-s1" --scene wild --seed 1 --motion handheld
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
