#!/usr/bin/env bash
# bench_lidar_translation: the LiDAR extrinsic's translation estimated in the LIO window
# (lio.estimate_lidar_translation; docs/METHOD.md "Online spatiotemporal calibration"). Simulated
# sequences (32-beam LiDAR + IMU; no camera, wheel or GNSS) whose given translation is off by --error m in a
# direction drawn from the seed (`sim --lidar-translation-error`): hand-held walks through the given scenes,
# and vehicle drives through --vehicle-scenes (a car turns about the vertical only: the estimate should stay
# put). Per case: the estimate's distance from the truth and its x, y, z (the true mount is (0, 0, 0.25) m),
# the window solves that moved it, and the ATE (SE3-aligned) with the given translation held, estimated,
# and the true one held, over the whole run and from 5 s on (the start, before the estimate settles, left
# out: the keyframes of that time are held and moved to the settled estimate; the map built then is not). configs/run-sim.yaml with lio.imu_deskew on (the estimate needs it) and the solve
# budget lifted (lo.max_solver_time_s: 10) so that the figures repeat.
#   usage: bench/bench_lidar_translation.sh [--duration S] [--error M] [--seeds "1 2 3"]
#                                           [--vehicle-scenes "urban"] [--keep DIR] [SCENE ...]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=30
error=0.1
seeds="1 2 3"
vehicle_scenes="urban"
keep=""
scenes=()
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --error) error="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --vehicle-scenes) vehicle_scenes="$2"; shift 2 ;;
    --keep) keep="$2"; shift 2 ;;
    *) scenes+=("$1"); shift ;;
  esac
done
((${#scenes[@]})) || scenes=(warehouse urban wild)
work="${keep:-$(mktemp -d)}"
[[ -n "$keep" ]] || trap 'rm -rf "$work"' EXIT
mkdir -p "$work"
held="$work/held.yaml"
sed -e 's/^  imu_deskew: false /  imu_deskew: true /' -e 's/^lo:$/lo:\n  max_solver_time_s: 10/' \
  "$root/configs/run-sim.yaml" >"$held"
grep -q "^  imu_deskew: true " "$held" || { echo "configs/run-sim.yaml: no imu_deskew line"; exit 1; }
sed 's/^  estimate_lidar_translation: false /  estimate_lidar_translation: true /' "$held" >"$work/estimated.yaml"
grep -q "^  estimate_lidar_translation: true " "$work/estimated.yaml" ||
  { echo "configs/run-sim.yaml: no estimate_lidar_translation line"; exit 1; }

# The lidar entry's translation (x y z) of a calibration file.
lidar_translation() {
  awk '/- name: lidar/ { on = 1 } on && /T_body_sensor/ { gsub(/.*\[|\].*/, ""); gsub(/,/, " ");
       printf "%.4f %.4f %.4f\n", $4, $8, $12; exit }' "$1"
}
ate() { sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$1" | head -1; }
# ATE (SE3-aligned) of the poses from 5 s after the first on: the run's first seconds, before the estimate
# settles, left out.
late_ate() {  # dataset, run folder
  awk '/^#/ { print; next } !t0 { t0 = $1 } $1 >= t0 + 5' "$2/trajectory.tum" >"$2/late.tum"
  "$bin" eval "$1/groundtruth.tum" "$2/late.tum" 2>/dev/null | awk '/^APE/ { print $3 }'
}
run_lio() {  # dataset, config, out: "ATE late-ATE"
  rm -rf "$3"
  "$bin" run "$1" --config "$2" --mode lio --no-map --out "$3" >"$3.log" 2>&1 || true
  echo "$(ate "$3.log") $([[ -f "$3/trajectory.tum" ]] && late_ate "$1" "$3")"
}

echo "bench_lidar_translation: ${duration} s, given translation ${error} m off, seeds $seeds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
echo "| case | seed | estimate from truth m | estimate x, y, z m | solves that moved it | ATE given m | ATE estimated m | ATE true m | from 5 s: given | estimated | true |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
run_case() {  # name, seed, sim arguments...
  local name="$1" seed="$2" data="$work/$1-s$2"; shift 2
  "$bin" sim "$@" --seed "$seed" --duration "$duration" --no-camera --no-wheel --no-gnss \
    --lidar-translation-error "$error" --out "$data" >/dev/null 2>&1 || { echo "$name $seed: sim failed"; return; }
  sed "s|^dataset:|&\n  calibration_file: $data/calibration_true.yaml|" "$held" >"$data-true.yaml"
  local given given_late estimated estimated_late truth truth_late t moved="-" off="-"
  read -r given given_late <<<"$(run_lio "$data" "$held" "$data-given")"
  read -r estimated estimated_late <<<"$(run_lio "$data" "$work/estimated.yaml" "$data-estimated")"
  read -r truth truth_late <<<"$(run_lio "$data" "$data-true.yaml" "$data-true")"
  t="- - -"
  if [[ -f "$data-estimated/calibration_estimated.yaml" ]]; then
    t=$(lidar_translation "$data-estimated/calibration_estimated.yaml")
    off=$(paste -d' ' <(echo "$t") <(lidar_translation "$data/calibration_true.yaml") |
      awk '{ printf "%.4f", sqrt(($1 - $4)^2 + ($2 - $5)^2 + ($3 - $6)^2) }')
    moved=$(sed -n 's/.*it moved in \([0-9]* of [0-9]*\) window solves.*/\1/p' "$data-estimated/report.md")
  fi
  echo "| $name | $seed | $off | $t | ${moved:--} | ${given:--} | ${estimated:--} | ${truth:--} |" \
    "${given_late:--} | ${estimated_late:--} | ${truth_late:--} |"
}
for seed in $seeds; do
  for scene in "${scenes[@]}"; do run_case "$scene-handheld" "$seed" --scene "$scene" --motion handheld; done
  for scene in $vehicle_scenes; do run_case "$scene-vehicle" "$seed" --scene "$scene"; done
done
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
