#!/usr/bin/env bash
# bench_long_run: the hour-long run of issue 22. Simulates `urban` for DURATION seconds (default 3600; a 16-beam
# LiDAR at 0.4 deg, ~11 GB for the hour, + IMU, no camera/wheel/GNSS), then runs LIO over it with the LiDAR withheld for 2 s of every 60 s
# (bench_long_run), reporting peak RSS, the RSS growth after the first 10 minutes, the real-time factor,
# non-finite poses and the ATE; rss_over_time.csv and rss_over_time.png land in the work folder.
#   usage: bench/bench_long_run.sh [--duration S] [--keep DIR]
# Expect about 10 min of simulation and 15-25 min of odometry on 2 cores.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}"
duration=3600
keep=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) echo "usage: $0 [--duration S] [--keep DIR]" >&2; exit 2 ;;
  esac
done
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
echo "bench_long_run: urban ${duration} s, load average $(cut -d' ' -f1-3 /proc/loadavg)"
printf 'sim:\n  lidar:\n    horizontal_resolution_deg: 0.4\n' >"$work/sim16.yaml"
[[ -f "$work/urban/lidar.bin" ]] ||
  "$bin/ultrafusion" sim --scene urban --duration "$duration" --lidar spinning16 --config "$work/sim16.yaml" \
    --no-camera --no-wheel --no-gnss --out "$work/urban" >/dev/null
"$bin/bench_long_run" "$work/urban" --out "$work" --dropout-every 60 --dropout-length 2
echo "RSS samples: $work/rss_over_time.csv, plot: $work/rss_over_time.png"
