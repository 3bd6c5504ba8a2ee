#!/usr/bin/env bash
# bench_handheld: issue 22's handheld figures. For each scene (default: warehouse, wild) and seed (default
# 1-10): `ultrafusion sim --motion handheld --lidar-rate 2` (20 s, 32-beam LiDAR swept at 10 Hz, one scan kept
# every 0.5 s, up to ~35 deg and 0.7 m between kept scans, IMU), then `ultrafusion run` in LO and in LIO with
# configs/run-sim.yaml and only the iteration budget (lo.max_solver_time_s lifted: the figures then do not
# depend on the machine's load). Prints the ATE (SE3-aligned) per run and the rejected scans / restarts, then
# per scene and mode the median, the worst and how many seeds met the issue's targets (LO <= 0.05 m,
# LIO <= 0.03 m). --imu-deskew: LIO with lio.imu_deskew on (the IMU's correction within each sweep).
#   usage: bench/bench_handheld.sh [--seeds N] [--keep DIR] [--imu-deskew] [SCENE ...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
seeds=10
keep=""
deskew=false
scenes=()
while (($#)); do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    --imu-deskew) deskew=true; shift ;;
    *) scenes+=("$1"); shift ;;
  esac
done
((${#scenes[@]})) || scenes=(warehouse wild)
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
sed -e 's/^lo:$/lo:\n  max_solver_time_s: 100/' -e "s/^  imu_deskew: false /  imu_deskew: $deskew /" \
  "$root/configs/run-sim.yaml" >"$work/run.yaml"
grep -q "^  imu_deskew: $deskew " "$work/run.yaml" || { echo "configs/run-sim.yaml: no imu_deskew line"; exit 1; }
echo "bench_handheld: ${seeds} seeds, lio.imu_deskew $deskew, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-10s %5s %-4s %10s %9s\n' scene seed mode ATE_m rejected
for scene in "${scenes[@]}"; do
  for mode in lo lio; do : >"$work/$scene-$mode.ate"; done
  for ((seed = 1; seed <= seeds; ++seed)); do
    seq="$work/$scene-$seed"
    [[ -f "$seq/lidar.bin" ]] || "$bin" sim --scene "$scene" --motion handheld --lidar-rate 2 --duration 20 \
      --no-camera --no-wheel --no-gnss --seed "$seed" --out "$seq" >/dev/null
    for mode in lo lio; do
      rm -rf "$seq-$mode"
      ate=$("$bin" run "$seq" --config "$work/run.yaml" --no-map --mode "$mode" --out "$seq-$mode" 2>&1 |
        sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p')
      events=$(grep -c '| rejected |\|| restarted |' "$seq-$mode/report.md" || true)
      printf '%-10s %5s %-4s %10s %9s\n' "$scene" "$seed" "$mode" "${ate:-failed}" "$events"
      echo "${ate:-1e9}" >>"$work/$scene-$mode.ate"
    done
  done
done
echo
printf '%-10s %-4s %10s %10s %s\n' scene mode median_m worst_m "met (LO <= 0.05, LIO <= 0.03)"
for scene in "${scenes[@]}"; do
  for mode in lo lio; do
    target=$([[ $mode == lo ]] && echo 0.05 || echo 0.03)
    sort -g "$work/$scene-$mode.ate" | awk -v s="$scene" -v m="$mode" -v t="$target" \
      '{a[NR]=$1; if ($1 <= t) met++} END {printf "%-10s %-4s %10.4f %10.4f %d of %d\n", s, m, (a[int((NR+1)/2)] + a[int(NR/2)+1]) / 2, a[NR], met+0, NR}'
  done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
