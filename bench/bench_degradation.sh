#!/usr/bin/env bash
# bench_degradation: the wheel, IMU, GNSS, LiDAR and camera cases of the degradation suite (docs/METHOD.md
# "Factor-wise reliability scheduling"). Simulated sequences whose wheels slip (`sim.wheel.slips`: the wheels turn 30 %
# too fast for 7 s, then 25 % too slow for 4 s) or leave the ground (`sim.wheel.floats`: the reading frozen
# for 2 s while the vehicle pulls away, and for 4 s while cruising), whose gyroscope clips
# (`sim.imu.gyro_saturation` 0.25 rad/s on `wild`, whose roll and pitch rates reach 0.6 rad/s), or whose RTK
# fixes suffer multipath (`sim.gnss.multipath`: 5 m north for 5 s from 12 s, 3 m east and 2 m up for 3 s
# from 20 s) and a 30 s outage from 25 s (`sim.gnss.outages`), or whose LiDAR is degenerate (`corridor`
# and `tunnel`: the scene's axis free; scene `lidar`), or whose camera is in the dark over 10-20 s with a dark
# occluder sliding over the lens over 22-26 s (`dark`) or sees a textured panel pass in front of it over
# 10-14 s and 22-26 s (`panel`, `sim.camera.passing_panels`; scene `camera`, no LiDAR, VIO and VWIO, 30 s
# at most), beside the same sequences without any; a noisy encoder in all (0.3 rad/s per wheel sample), no
# camera outside the camera cases, GNSS only in the GNSS cases. Each runs with
# the reliability scheduling on (the default; with the clipping gyro, its full scale given as
# `imu.gyro_range`, as a datasheet would) and off (the ablation: `lio|wio.wheel.schedule.enabled: false`,
# no range, the GNSS innovation test's gate at 1e9 and no step guard, and the LiDAR's weak translations
# not left to the wheel: `lio.wheel_carries_weak_translations: false`; in the camera cases on is
# `lio|wio.visual.schedule.enabled: true`, off by default), the solves' time budget lifted, in
# WIO and LWIO on `urban` and `wild`, in LWIO on `corridor` (where the LiDAR leaves the axis to the wheel),
# in WGIO and LWGIO for the GNSS cases and in LWIO for the LiDAR cases, against the simulator's ground
# truth, the scheduled ATE also per 100 m driven. The GNSS cases add how far
# the multipath moved the trajectory (the largest horizontal distance, in ENU, from the run without faults
# over 12-25 s) and the re-initializations through the outage. Writes a markdown table, and one of each
# modality's mean ATE change over its degraded runs beside the paper's, to stdout and suite.md (with
# suite.json) into --out (default: a temporary folder). Takes ~30 min on 2 cores; the camera
# cases, ~35 min more, run when named (--scenes camera), not by default.
#   usage: bench/bench_degradation.sh [--duration S] [--seeds "1 2 3"]
#          [--scenes "urban corridor wild gnss lidar camera"]
#          [--quick] [--out DIR]
# --quick: 30 s, seed 1 (~3 min). An unknown argument or scene exits 2 naming it; a case whose simulation
# or run fails gets a row saying so (in suite.json its "error"), and the others still run
# (tests/scripts/test_bench_degradation.sh).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
seeds="1 2 3"
scenes="urban corridor wild gnss lidar"
out=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --scenes) scenes="$2"; shift 2 ;;
    --quick) duration=30; seeds="1"; shift ;;
    --out) out="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
for scene in $scenes; do
  case "$scene" in
    urban | corridor | wild | gnss | lidar | camera) ;;
    *) echo "unknown scene '$scene' (urban, corridor, wild, gnss, lidar, camera)" >&2; exit 2 ;;
  esac
done
work="${out:-$(mktemp -d)}"
mkdir -p "$work"

# The configs: configs/run-sim.yaml with scheduling on (as it is) and off, both with the solves' time
# budget lifted (only their iteration limits: the figures do not depend on the machine's load).
on="$work/schedule-on.yaml"
off="$work/schedule-off.yaml"
# run-sim.yaml has a visual: section in both lio: and wio: (the smoothing of the simulator's camera).
camera_budget='    max_solver_time_s: 10'
unscheduled_camera="$camera_budget"'\n    schedule:\n      enabled: false'
unscheduled='  wheel:\n    schedule:\n      enabled: false\n  gnss:\n    integrity_gate: 1e9\n    step_max_hold_s: 0'
sed -e 's/^lo:$/lo:\n  max_solver_time_s: 10/' -e 's/^wio:$/wio:\n  max_solver_time_s: 10/' \
  -e "s/^  visual:$/  visual:\n$camera_budget/" "$root/configs/run-sim.yaml" >"$on"
sed -e 's/^lo:$/lo:\n  max_solver_time_s: 10/' -e "s/^wio:$/wio:\n  max_solver_time_s: 10\n$unscheduled/" \
  -e "s/^lio:$/lio:\n  wheel_carries_weak_translations: false\n$unscheduled/" \
  -e "s/^  visual:$/  visual:\n$unscheduled_camera/" "$root/configs/run-sim.yaml" >"$off"
# With the clipping gyro, scheduling on knows its full scale.
on_clip="$work/schedule-on-clip.yaml"
sed -e 's/^  imu:$/  imu:\n    gyro_range: 0.25/' -e 's/^wio:$/wio:\n  imu:\n    gyro_range: 0.25/' "$on" >"$on_clip"
# In the camera cases, scheduling on leaves out the frames whose tracks disagree with the predicted motion
# (off by default).
on_camera="$work/schedule-on-camera.yaml"
sed 's/^    max_solver_time_s: 10$/    max_solver_time_s: 10\n    schedule:\n      enabled: true/' "$on" >"$on_camera"

# A sequence: scene, seed, slips ("[]" for none), floats ("[]" for none), gyro saturation (0: none), GNSS
# ("none", "clean" RTK fixes, "faulty": with the multipath and the outage), out, and the camera ("none",
# or without the LiDAR: "clean", "dark" with the darkness and the occluder, "panel" with the passing panels).
simulate() {
  local gnss=(--no-gnss) multipath="[]" outages="[]" sensors=(--no-camera) darkness="[]" occlusions="[]" panels="[]"
  [[ $6 != none ]] && gnss=()
  [[ $6 == faulty ]] && multipath="$gnss_multipath" && outages="$gnss_outages"
  [[ ${8:-none} != none ]] && sensors=(--lidar none)
  [[ ${8:-none} == dark ]] && darkness="$camera_darkness" && occlusions="$camera_occlusions"
  [[ ${8:-none} == panel ]] && panels="$camera_panels"
  "$bin" sim --scene "$1" --seed "$2" --duration "$case_duration" "${sensors[@]}" "${gnss[@]}" --print-config |
    sed -e 's/^    wheel_speed_noise_std: 0$/    wheel_speed_noise_std: 0.3/' \
        -e "s/^    slips: \[\]/    slips: $3/" -e "s/^    floats: \[\]/    floats: $4/" \
        -e "s/^    gyro_saturation: 0$/    gyro_saturation: $5/" -e 's/^    quality: single$/    quality: rtk_fixed/' \
        -e "s/^    multipath: \[\]/    multipath: $multipath/" -e "s/^    outages: \[\]/    outages: $outages/" \
        -e "s/^    darkness: \[\]/    darkness: $darkness/" -e "s/^    occlusions: \[\]/    occlusions: $occlusions/" \
        -e "s/^    passing_panels: \[\]/    passing_panels: $panels/" >"$7.yaml"
  rm -rf "$7"
  "$bin" sim --config "$7.yaml" --out "$7" >"$7.sim.log" 2>&1
}
ate() { sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$1" | head -1; }
# dataset, mode, config, out: "ATE wheel-intervals-left-out GNSS-fixes-rejected re-initializations
# camera-frames-left-out"
run() {
  rm -rf "$4"
  "$bin" run "$1" --config "$3" --mode "$2" --no-map --out "$4" >"$4.log" 2>&1 || true
  local wheel=0 gnss=0 restarts=0 camera=0 value
  if [[ -f "$4/reliability.csv" ]]; then
    wheel=$(awk -F, '$2 == "wheel" && $4 == 0' "$4/reliability.csv" | wc -l)
    gnss=$(awk -F, '$2 == "gnss" && $4 == 0' "$4/reliability.csv" | wc -l)
    camera=$(awk -F, '$2 == "camera" && $4 == 0' "$4/reliability.csv" | wc -l)
  fi
  [[ -f "$4/report.md" ]] && restarts=$(grep -c "re-initializing" "$4/report.md" || true)
  value=$(ate "$4.log")
  echo "${value:--} $wheel $gnss $restarts $camera"
}

slips="[{window: [15, 22], ratio: 0.3}, {window: [38, 42], ratio: -0.25}]"
floats="[[3, 5], [20, 24]]"
gnss_multipath="[{window: [12, 17], offset_m: [0, 5, 0]}, {window: [20, 23], offset_m: [3, 0, 2]}]"
gnss_outages="[[25, 55]]"
camera_darkness="[[10, 20]]"
camera_occlusions="[[22, 26]]"
camera_panels="[[10, 14], [22, 26]]"
# The largest horizontal distance (m) between two trajectory.tum (ENU) at their common stamps, over
# [12, 25) s after the sequence's start (its ground truth's first stamp): what the multipath moved.
moved() {
  [[ -f "$1" && -f "$2" ]] || { echo "-"; return; }
  local start
  start=$(awk '!/^#/ { print $1; exit }' "$3")
  awk -v start="$start" 'FNR == 1 { file++ } /^#/ { next }
    file == 1 { x[$1] = $2; y[$1] = $3; next }
    ($1 in x) && $1 - start >= 12 && $1 - start < 25 {
      d = sqrt(($2 - x[$1]) ^ 2 + ($3 - y[$1]) ^ 2); if (d > m) m = d }
    END { printf "%.3f", m }' "$2" "$1"
}
echo "bench_degradation: ${duration} s, seeds $seeds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
json="$work/suite.json"
changes="$work/changes.txt"  # "scene ATE-scheduled ATE-unscheduled" per degraded run
: >"$changes"
echo "[" >"$json"
first=1
# Appends one case's JSON object (its text as the arguments' printf) to suite.json.
json_row() {
  ((first)) || echo "," >>"$json"
  first=0
  # shellcheck disable=SC2059
  printf "$@" >>"$json"
}
# The last line of a log, as a table cell and a JSON string can hold it.
last_line() { tail -1 "$1" 2>/dev/null | tr '|"\\' '/  '; }
{
  echo "| case | mode | seed | driven m | ATE scheduled m | per 100 m | ATE unscheduled m | change | wheel intervals left out | camera frames left out | GNSS fixes rejected | multipath moved it, m (scheduled / not) | re-initializations |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
} | tee "$work/suite.md"
for seed in $seeds; do
  for scene in $scenes; do
    kinds="clean slip float" sim_scene="$scene" modes="wio lwio"
    [[ $scene == wild ]] && kinds="clean clip"
    [[ $scene == corridor ]] && modes="lwio"
    [[ $scene == gnss ]] && kinds="clean multipath" sim_scene="urban" modes="wgio lwgio"
    [[ $scene == lidar ]] && kinds="corridor tunnel" modes="lwio"
    [[ $scene == camera ]] && kinds="clean dark panel" sim_scene="urban" modes="vio vwio"
    case_duration=$duration  # the camera's cases at most 30 s: its runs are the slowest, its events end at 26 s
    [[ $scene == camera ]] && case_duration=$((duration < 30 ? duration : 30))
    for kind in $kinds; do
      data="$work/$scene-$kind-s$seed"
      gnss=none
      [[ $scene == gnss ]] && gnss="$([[ $kind == multipath ]] && echo faulty || echo clean)"
      [[ $scene == lidar ]] && sim_scene="$kind"
      camera=none
      [[ $scene == camera ]] && camera="$kind"
      simulate "$sim_scene" "$seed" "$([[ $kind == slip ]] && echo "$slips" || echo "[]")" \
        "$([[ $kind == float ]] && echo "$floats" || echo "[]")" "$([[ $kind == clip ]] && echo 0.25 || echo 0)" \
        "$gnss" "$data" "$camera" || {
        error="simulation failed: $(last_line "$data.sim.log")"
        echo "| $scene-$kind | - | $seed | $error | | | | | | | | | |" | tee -a "$work/suite.md"
        json_row '{"case": "%s-%s", "seed": %s, "error": "%s"}' "$scene" "$kind" "$seed" "$error"
        continue
      }
      config="$on"
      [[ $kind == clip ]] && config="$on_clip"
      [[ $scene == camera ]] && config="$on_camera"
      driven=$(awk '!/^#/ { if (n++) d += sqrt(($2 - x) ^ 2 + ($3 - y) ^ 2 + ($4 - z) ^ 2); x = $2; y = $3; z = $4 }
        END { printf "%.0f", d }' "$data/groundtruth.tum")
      for mode in $modes; do
        read -r with wheel gnss_rejected restarts camera_left_out <<<"$(run "$data" "$mode" "$config" "$data-$mode-on")"
        read -r without _ _ _ _ <<<"$(run "$data" "$mode" "$off" "$data-$mode-off")"
        change=$(awk -v a="${with:-nan}" -v b="${without:-nan}" 'BEGIN { if (a != "-" && b != "-" && b > 0) printf "%+.0f %%", 100 * (a - b) / b; else print "-" }')
        error=""
        [[ $without == - ]] && error="failed without scheduling: $(last_line "$data-$mode-off.log")"
        [[ $with == - ]] && error="failed: $(last_line "$data-$mode-on.log")"
        [[ -z $error ]] || change="$error"
        moved_by="-"
        if [[ $kind == multipath ]]; then
          clean="$work/$scene-clean-s$seed-$mode"
          moved_by="$(moved "$data-$mode-on/trajectory.tum" "$clean-on/trajectory.tum" "$data/groundtruth.tum") / $(moved "$data-$mode-off/trajectory.tum" "$clean-off/trajectory.tum" "$data/groundtruth.tum")"
        fi
        per100=$(awk -v a="$with" -v d="$driven" 'BEGIN { if (a != "-" && d > 0) printf "%.3f", 100 * a / d; else print "-" }')
        echo "| $scene-$kind | $mode | $seed | $driven | ${with:--} | $per100 | ${without:--} | $change | $wheel | $camera_left_out | $gnss_rejected | $moved_by | $restarts |" | tee -a "$work/suite.md"
        json_row '{"case": "%s-%s", "mode": "%s", "seed": %s, "driven_m": %s, "ate_scheduled_m": "%s", "ate_scheduled_per_100m": "%s", "ate_unscheduled_m": "%s", "wheel_intervals_left_out": %s, "camera_frames_left_out": %s, "gnss_fixes_rejected": %s, "multipath_moved_m": "%s", "reinitializations": %s, "error": "%s"}' \
          "$scene" "$kind" "$mode" "$seed" "$driven" "${with:--}" "$per100" "${without:--}" "$wheel" "$camera_left_out" "$gnss_rejected" "$moved_by" "$restarts" "$error"
        [[ $kind == clean || -n $error ]] || echo "$scene $with $without" >>"$changes"
      done
    done
  done
done
echo "]" >>"$json"
# The mean ATE change of each modality's degraded runs, beside the paper's mean reduction with its
# scheduling (LiDAR 75 %, camera 36 %, wheel 41 %; it gives none for the IMU and GNSS).
{
  echo
  echo "| modality | degraded runs | mean ATE change, scheduled against not | the paper's |"
  echo "|---|---|---|---|"
  awk 'BEGIN { m["urban"] = m["corridor"] = "wheel"; m["wild"] = "imu"; m["gnss"] = "gnss"; m["lidar"] = "lidar"
               m["camera"] = "camera"; p["wheel"] = "-41 %"; p["lidar"] = "-75 %"; p["camera"] = "-36 %" }
       $3 > 0 { k = m[$1]; n[k]++; s[k] += 100 * ($2 - $3) / $3 }
       END { for (k in n) printf "| %s | %d | %+.0f %% | %s |\n", k, n[k], s[k] / n[k], (k in p) ? p[k] : "-" }' "$changes" |
    sort
} | tee -a "$work/suite.md"
echo "wrote $work/suite.md, $work/suite.json; load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
