#!/usr/bin/env bash
# bench_vio: visual-inertial odometry (`ultrafusion run --mode vio`) on simulated urban drives (IMU + the
# forward 640 x 480 camera; no LiDAR, wheel or GNSS) for the given seeds (default 1 2 3, 60 s), rendered
# without anti-aliasing (the simulator's default, supersampling 1) and with 2 x 2 rays per pixel (the blur a
# real lens gives). Prints per seed the ATE and the KITTI-style drift against the simulator's ground truth,
# the time per node, and the means, with the load average (2 shared cores).
#   usage: bench/bench_vio.sh [--duration S] [--seeds "1 2 3"] [--supersampling "1 2"] [--delay S]
#                             [--stereo B] [--smoothing SIGMA] [--config FILE] [--keep DIR]
# --delay S: the camera stamps run S late (sim --camera-stamp-delay) and the run estimates t_d
# (wio.visual.estimate_time_offset); the table adds the estimate (the truth is -S).
# --stereo B: a stereo rig, a second camera B m to the right of the first (sim --stereo-baseline; the run
# uses it, wio.visual.stereo); the first camera's frames are the same as without it.
# --smoothing SIGMA: the front end's smoothing of the frames, px (wio.visual.tracker.smoothing_sigma_px;
# default 0.8, as configs/run-sim.yaml for the simulator's camera; 0: none). Not with --config.
# --keep DIR keeps the sequences and runs there, and reuses the sequences found there on the next call.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
seeds="1 2 3"
supersampling="1 2"
delay=""
stereo=""
config=""
smoothing=0.8
keep=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --supersampling) supersampling="$2"; shift 2 ;;
    --delay) delay="$2"; shift 2 ;;
    --stereo) stereo="$2"; shift 2 ;;
    --smoothing) smoothing="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) echo "bench_vio: unknown argument $1" >&2; exit 2 ;;
  esac
done
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
run_config="$work/run.yaml"
if [[ -n "$config" ]]; then
  cp "$config" "$run_config"
  if [[ -n "$delay" ]]; then
    grep -q '^wio:' "$run_config" && { echo "bench_vio: --delay with a config that has wio: is not supported" >&2; exit 2; }
    printf 'wio:\n  visual:\n    estimate_time_offset: true\n' >>"$run_config"
  fi
else
  printf 'wio:\n  visual:\n    tracker:\n      smoothing_sigma_px: %s\n' "$smoothing" >"$run_config"
  [[ -z "$delay" ]] || printf '    estimate_time_offset: true\n' >>"$run_config"
fi
settings=", smoothing $smoothing px"
[[ -z "$config" ]] || settings=", config $config"
echo "bench_vio: urban ${duration} s, seeds $seeds, supersampling $supersampling$settings${delay:+, camera delay $delay s}${stereo:+, stereo baseline $stereo m}, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%5s %5s %9s %9s %13s %9s %9s\n' ss seed ATE_m drift_% rot_deg/100m ms/node t_d_s
for ss in $supersampling; do
  sum_ate=0 sum_drift=0 n=0
  for seed in $seeds; do
    data="$work/urban-$seed-${duration}s-ss$ss${delay:+-d$delay}${stereo:+-st$stereo}"
    if [[ ! -f "$data/dataset.yaml" ]]; then
      rm -rf "$data"
      printf 'sim:\n  camera:\n    supersampling: %s\n' "$ss" >"$data.sim.yaml"
      "$bin" sim --scene urban --seed "$seed" --duration "$duration" --lidar none --no-wheel --no-gnss \
        --config "$data.sim.yaml" ${delay:+--camera-stamp-delay "$delay"} ${stereo:+--stereo-baseline "$stereo"} \
        --out "$data" >"$data.sim.log" 2>&1 ||
        { echo "seed $seed: sim failed, see $data.sim.log"; continue; }
    fi
    rm -rf "$data-vio"
    "$bin" run "$data" --config "$run_config" --mode vio --out "$data-vio" >"$data-vio.log" 2>&1 ||
      { echo "seed $seed: run failed, see $data-vio.log"; continue; }
    "$bin" eval --kitti-drift "$data/groundtruth.tum" "$data-vio/trajectory.tum" >"$data-vio.eval" 2>&1 || true
    ate=$(awk '/^APE/ { print $3 }' "$data-vio.eval")
    drift=$(sed -n 's/.*KITTI drift: \([0-9.]*\) % translation, \([0-9.]*\) deg.*/\1 \2/p' "$data-vio.eval")
    ms=$(sed -n 's/.* \([0-9.]*\) ms\/node mean.*/\1/p' "$data-vio.log" | head -1)
    td=$(sed -n 's/.*camera time offset t_d \(-*[0-9.]*\) s.*/\1/p' "$data-vio/report.md" | head -1)
    [[ -n "$ate" && -n "$drift" ]] || { echo "seed $seed: no figures, see $data-vio.eval"; continue; }
    read -r t r <<<"$drift"
    printf '%5s %5s %9s %9s %13s %9s %9s\n' "$ss" "$seed" "$ate" "$t" "$r" "${ms:--}" "${td:--}"
    read -r sum_ate sum_drift n < <(awk -v a="$sum_ate" -v b="$sum_drift" -v c="$n" -v x="$ate" -v y="$t" \
      'BEGIN { print a + x, b + y, c + 1 }')
  done
  ((n)) && awk -v s="$ss" -v a="$sum_ate" -v b="$sum_drift" -v n="$n" \
    'BEGIN { printf "%5s %5s %9.4f %9.3f   (mean of %d)\n", s, "mean", a / n, b / n, n }'
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
