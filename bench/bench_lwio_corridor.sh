#!/usr/bin/env bash
# bench_lwio_corridor: LIO against LIO + wheel (`ultrafusion run --mode lio` and `--mode lwio`) on simulated
# sequences of the given scenes and seeds (default: corridor, urban, tunnel; seeds 1 2 3; 60 s; 32-beam
# LiDAR + IMU + the simulator's default wheel odometry, no camera or GNSS). Prints the ATE of both modes
# against the simulator's ground truth (SE3-aligned, and aligned by yaw and translation only: a tilt of the
# gravity-aligned world counts there), their ratio LWIO / LIO (SE3) and the estimated wheel scale, per seed,
# and the mean per scene, with the load average (2 shared cores: timings are not the point here, the ATE is).
#   usage: bench/bench_lwio_corridor.sh [--duration S] [--seeds "1 2 3"] [--config FILE] [--keep DIR] [SCENE ...]
# --keep DIR keeps the sequences and runs there, and reuses the sequences found there (same scene, seed and
# duration) on the next call. The corridor and the tunnel are LiDAR-degenerate along their axis: the wheel's
# forward speed is what should carry that direction (docs/METHOD.md "Wheel factor", "In the LIO window").
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
seeds="1 2 3"
config="$root/configs/run-sim.yaml"
keep=""
scenes=()
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
((${#scenes[@]})) || scenes=(corridor urban tunnel)
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
ate() { sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$1" | head -1; }
yaw_ate() { sed -n 's/.*ATE (yaw-aligned RMSE, a tilt counts): \([0-9.]*\) m.*/\1/p' "$1" | head -1; }
echo "bench_lwio_corridor: ${duration} s, seeds $seeds, config $config, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-10s %5s %10s %10s %8s %8s %10s %10s\n' scene seed LIO_ATE_m LWIO_ATE_m ratio scale LIO_yaw_m LWIO_yaw_m
for scene in "${scenes[@]}"; do
  sum_lio=0 sum_lwio=0 sum_ratio=0 n=0
  for seed in $seeds; do
    data="$work/$scene-$seed-${duration}s"
    if [[ ! -f "$data/dataset.yaml" ]]; then
      rm -rf "$data"
      "$bin" sim --scene "$scene" --seed "$seed" --duration "$duration" --no-camera --no-gnss --out "$data" \
        >"$data.sim.log" 2>&1 || { echo "$scene $seed: sim failed, see $data.sim.log"; continue; }
    fi
    for mode in lio lwio; do
      rm -rf "$data-$mode"
      "$bin" run "$data" --config "$config" --no-map --mode "$mode" --out "$data-$mode" >"$data-$mode.log" 2>&1 ||
        echo "$scene $seed: $mode run failed, see $data-$mode.log"
    done
    lio=$(ate "$data-lio.log") lwio=$(ate "$data-lwio.log")
    scale=$(sed -n 's/.*estimated wheel scale \([0-9.]*\).*/\1/p' "$data-lwio/report.md" | head -1)
    [[ -n "$lio" && -n "$lwio" ]] || { echo "$scene $seed: no ATE"; continue; }
    ratio=$(awk -v a="$lwio" -v b="$lio" 'BEGIN { printf "%.3f", a / b }')
    printf '%-10s %5s %10s %10s %8s %8s %10s %10s\n' "$scene" "$seed" "$lio" "$lwio" "$ratio" "${scale:--}" \
      "$(yaw_ate "$data-lio.log")" "$(yaw_ate "$data-lwio.log")"
    read -r sum_lio sum_lwio sum_ratio n < <(awk -v a="$sum_lio" -v b="$sum_lwio" -v c="$sum_ratio" -v d="$n" \
      -v x="$lio" -v y="$lwio" -v r="$ratio" 'BEGIN { print a + x, b + y, c + r, d + 1 }')
  done
  ((n)) && awk -v s="$scene" -v a="$sum_lio" -v b="$sum_lwio" -v c="$sum_ratio" -v n="$n" \
    'BEGIN { printf "%-10s %5s %10.4f %10.4f %8.3f   (mean of %d; ratio of the means %.3f)\n", s, "mean", a / n, b / n, c / n, n, b / a }'
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
