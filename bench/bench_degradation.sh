#!/usr/bin/env bash
# bench_degradation: the wheel cases of the degradation suite (docs/METHOD.md "Factor-wise reliability
# scheduling"). Simulated sequences whose wheels slip (`sim.wheel.slips`: the wheels turn 30 % too fast for
# 7 s, then 25 % too slow for 4 s) or leave the ground (`sim.wheel.floats`: the reading frozen for 2 s while
# the vehicle pulls away, and for 4 s while cruising), beside the same sequences without either; a noisy
# encoder in all (0.3 rad/s per wheel sample), no camera or GNSS. Each runs with the wheel's reliability
# scheduling on (the default) and off (`lio|wio.wheel.schedule.enabled: false`, the ablation), the solves'
# time budget lifted, in WIO and LWIO on `urban` and in LWIO on `corridor` (where the LiDAR leaves the axis
# to the wheel), against the simulator's ground truth. Writes a markdown table to stdout and suite.md /
# suite.json into --out (default: a temporary folder). Takes ~10 min on 2 cores.
#   usage: bench/bench_degradation.sh [--duration S] [--seeds "1 2 3"] [--out DIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="${UF_BIN:-$root/build/bin}/ultrafusion"
duration=60
seeds="1 2 3"
out=""
while (($#)); do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "unknown argument $1" >&2; exit 2 ;;
  esac
done
work="${out:-$(mktemp -d)}"
mkdir -p "$work"

# The configs: configs/run-sim.yaml with scheduling on (as it is) and off, both with the solves' time
# budget lifted (only their iteration limits: the figures do not depend on the machine's load).
on="$work/schedule-on.yaml"
off="$work/schedule-off.yaml"
sed 's/^lo:$/lo:\n  max_solver_time_s: 10/' "$root/configs/run-sim.yaml" >"$on"
sed 's/^lio:$/lio:\n  wheel:\n    schedule:\n      enabled: false/' "$on" >"$off"
printf '\nwio:\n  max_solver_time_s: 10\n' >>"$on"
printf '\nwio:\n  max_solver_time_s: 10\n  wheel:\n    schedule:\n      enabled: false\n' >>"$off"

# A sequence: scene, seed, slips ("[]" for none), floats ("[]" for none), out.
simulate() {
  "$bin" sim --scene "$1" --seed "$2" --duration "$duration" --no-camera --no-gnss --print-config |
    sed -e 's/^    wheel_speed_noise_std: 0$/    wheel_speed_noise_std: 0.3/' \
        -e "s/^    slips: \[\]/    slips: $3/" -e "s/^    floats: \[\]/    floats: $4/" >"$5.yaml"
  rm -rf "$5"
  "$bin" sim --config "$5.yaml" --out "$5" >"$5.sim.log" 2>&1
}
ate() { sed -n 's/.*ATE (SE3-aligned RMSE): \([0-9.]*\) m.*/\1/p' "$1" | head -1; }
run() {  # dataset, mode, config, out: "ATE suppressed-intervals"
  rm -rf "$4"
  "$bin" run "$1" --config "$3" --mode "$2" --no-map --out "$4" >"$4.log" 2>&1 || true
  local suppressed=0
  [[ -f "$4/reliability.csv" ]] && suppressed=$(awk -F, '$2 == "wheel" && $4 == 0' "$4/reliability.csv" | wc -l)
  echo "$(ate "$4.log") $suppressed"
}

slips="[{window: [15, 22], ratio: 0.3}, {window: [38, 42], ratio: -0.25}]"
floats="[[3, 5], [20, 24]]"
echo "bench_degradation: ${duration} s, seeds $seeds, load average $(cut -d' ' -f1-3 /proc/loadavg)"
json="$work/suite.json"
echo "[" >"$json"
first=1
{
  echo "| case | mode | seed | ATE scheduled m | ATE unscheduled m | change | intervals left out |"
  echo "|---|---|---|---|---|---|---|"
} | tee "$work/suite.md"
for seed in $seeds; do
  for scene in urban corridor; do
        for kind in clean slip float; do
      data="$work/$scene-$kind-s$seed"
      simulate "$scene" "$seed" "$([[ $kind == slip ]] && echo "$slips" || echo "[]")" \
        "$([[ $kind == float ]] && echo "$floats" || echo "[]")" "$data" ||
        { echo "$scene-$kind $seed: sim failed, see $data.sim.log"; continue; }
      modes="lwio"
      [[ $scene == urban ]] && modes="wio lwio"
      for mode in $modes; do
        read -r with suppressed <<<"$(run "$data" "$mode" "$on" "$data-$mode-on")"
        read -r without _ <<<"$(run "$data" "$mode" "$off" "$data-$mode-off")"
        change=$(awk -v a="${with:-nan}" -v b="${without:-nan}" 'BEGIN { if (b > 0) printf "%+.0f %%", 100 * (a - b) / b; else print "-" }')
        echo "| $scene-$kind | $mode | $seed | ${with:--} | ${without:--} | $change | $suppressed |" | tee -a "$work/suite.md"
        ((first)) || echo "," >>"$json"
        first=0
        printf '{"case": "%s-%s", "mode": "%s", "seed": %s, "ate_scheduled_m": "%s", "ate_unscheduled_m": "%s", "intervals_left_out": %s}' \
          "$scene" "$kind" "$mode" "$seed" "${with:--}" "${without:--}" "$suppressed" >>"$json"
      done
    done
  done
done
echo "]" >>"$json"
echo "wrote $work/suite.md, $work/suite.json; load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
