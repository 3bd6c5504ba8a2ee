#!/usr/bin/env bash
# bench/bench_degradation.sh's harness without the estimator: an unknown argument or scene exits 2 naming it,
# and a case whose simulation or run fails gets a row (and a JSON object) carrying its error while the others
# still run. The simulator and the runs are a stub ultrafusion (UF_BIN): its sim fails with STUB_SIM_FAIL
# set, else writes a three-pose ground truth; its run fails in WIO and reports an ATE of 0.5 m otherwise.
# Usage: test_bench_degradation.sh SOURCE_DIR
set -uo pipefail
bench="$1/bench/bench_degradation.sh"
command -v python3 >/dev/null || { echo "SKIP: no python3 to read the suite's JSON"; exit 77; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fail() {
  echo "FAIL $*"
  failures=$((failures + 1))
}
cat >"$work/ultrafusion" <<'STUB'
#!/usr/bin/env bash
case "$*" in
  *--print-config*) echo "sim: {}" ;;
  sim\ *)
    [[ -z "${STUB_SIM_FAIL:-}" ]] || { echo "error: stub simulation failure" >&2; exit 1; }
    out="${*: -1}"
    mkdir -p "$out" && printf '0 0 0 0 0 0 0 1\n1 3 4 0 0 0 0 1\n2 3 4 12 0 0 0 1\n' >"$out/groundtruth.tum" ;;
  run\ *)
    [[ " $* " != *" --mode wio "* ]] || { echo "error: stub run failure in \"wio\" | here"; exit 1; }
    mkdir -p "${*: -1}" && echo "ATE (SE3-aligned RMSE): 0.5000 m" ;;
  *) exit 1 ;;
esac
STUB
chmod +x "$work/ultrafusion"

expect_exit() {  # NAME WANTED_EXIT PATTERN -- command...
  local name=$1 wanted=$2 pattern=$3 output code
  shift 4
  output=$("$@" 2>&1)
  code=$?
  if [[ $code != "$wanted" ]] || ! grep -qE -- "$pattern" <<<"$output"; then
    fail "$name: exit $code (wanted $wanted), output without /$pattern/:"
    echo "$output" | tail -20
  else
    echo "ok   $name"
  fi
}
export UF_BIN="$work"
expect_exit "unknown argument" 2 "unknown argument --frobnicate" -- "$bench" --frobnicate
expect_exit "unknown scene" 2 "unknown scene 'nowhere'" -- "$bench" --scenes "urban nowhere"

# Every simulation fails: a row per case (wild: clean and clip), each with the simulator's error.
STUB_SIM_FAIL=1 expect_exit "failed simulations" 0 "wrote" -- "$bench" --quick --scenes wild --out "$work/sim"
rows=$(grep -c "simulation failed: error: stub simulation failure" "$work/sim/suite.md")
[[ $rows == 2 ]] || fail "failed simulations: $rows rows with the error in suite.md, wanted 2"
# The WIO runs fail: their rows carry the run's last line; the LWIO rows have their figures.
expect_exit "failed runs" 0 "wrote" -- "$bench" --quick --scenes urban --out "$work/run"
rows=$(grep -c '| wio | 1 | 17 | - | - | - | failed: error: stub run failure in  wio  / here |' "$work/run/suite.md")
[[ $rows == 3 ]] || fail "failed runs: $rows WIO rows with the error, wanted 3"
rows=$(grep -c '| lwio | 1 | 17 | 0.5000 | 2.941 | 0.5000 | +0 % |' "$work/run/suite.md")
[[ $rows == 3 ]] || fail "failed runs: $rows LWIO rows with their figures, wanted 3"
# The wheel's degraded runs that did not fail (LWIO slip and float) make its mean, beside the paper's.
grep -qF '| wheel | 2 | +0 % | -41 % |' "$work/run/suite.md" || fail "failed runs: no wheel mean over 2 runs"
for suite in sim run; do
  python3 - "$work/$suite/suite.json" <<'PY' || fail "$suite/suite.json"
import json, sys
rows = json.load(open(sys.argv[1]))
errors = [r for r in rows if r.get("error")]
want = (2, 2) if "sim/" in sys.argv[1] else (6, 3)
assert (len(rows), len(errors)) == want, (len(rows), len(errors))
PY
done
((failures == 0)) && echo "all passed"
exit $((failures > 0))
