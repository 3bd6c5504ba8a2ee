#!/usr/bin/env bash
# bench_wio.sh: wheel-inertial odometry on the simulated urban sequence (issue 20's WIO figure: translational
# drift <= 1.0 % on urban 60 s): makes the sequence with the built `ultrafusion sim` (no camera, no GNSS; the
# LiDAR stays on and is unused) and runs build/bin/bench_wio over it.
#   usage: bench/bench_wio.sh [--duration S] [--scene NAME] [--keep DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}"
duration=60
scene=urban
keep=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
rm -rf "$work/$scene"
"$bin/ultrafusion" sim --scene "$scene" --duration "$duration" --no-camera --no-gnss --out "$work/$scene" >/dev/null
"$bin/bench_wio" "$work/$scene" --out "$work/$scene-wio.tum"
