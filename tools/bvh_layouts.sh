#!/usr/bin/env bash
# The GPU's two trees side by side on every built-in (issue 42): `refract render --device gpu
# --estimator path` with the compressed wide BVH (REFRACT_GPU_BVH=cwbvh, the default) and
# with the BVH2 (REFRACT_GPU_BVH=bvh2), and with a second binary ($BEFORE, e.g. a build of the
# commit before the CWBVH) where given — alternated ROUNDS times per scene, so that a busy
# machine slows each alike. One line per render, then per scene the mean samples/s of each
# and the ratios. Works on lavapipe and on a hardware GPU.
#
#   BIN=target/release/refract [BEFORE=/path/to/old/refract] [W=128 H=96 SPP=8 ROUNDS=2] \
#     tools/bvh_layouts.sh [scene…]
set -uo pipefail
cd "$(dirname "$0")/.."
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
BIN="${BIN:-target/release/refract}"
BEFORE="${BEFORE:-}"
W="${W:-128}" H="${H:-96}" SPP="${SPP:-8}" ROUNDS="${ROUNDS:-2}"
OUT="${OUT:-$(mktemp -d)}"
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(cornell-glass glass-slab furnace rough-glass prism caustic \
  materials caustic-mirror glass-of-water env-spheres sun-sky ior-grid transmission-roughness metals)
# One render: its samples/s (M) on stdout.
render() {
  local bin=$1 tree=$2 scene=$3
  REFRACT_GPU_BVH=$tree "$bin" render --scene "builtin:$scene" --device gpu --estimator path \
    --width "$W" --height "$H" --spp "$SPP" --out "$OUT/$scene.exr" 2>&1 |
    sed -n 's/.* \([0-9.]*\) M samples\/s.*/\1/p' | tail -1
}
echo "scene | variant | M samples/s per round"
for s in "${scenes[@]}"; do
  declare -A sum=()
  variants=("$BIN cwbvh" "$BIN bvh2")
  [ -n "$BEFORE" ] && variants+=("$BEFORE bvh2")
  for ((r = 0; r < ROUNDS; r++)); do
    for v in "${variants[@]}"; do
      read -r bin tree <<<"$v"
      label=$([ "$bin" = "$BEFORE" ] && echo before || echo "$tree")
      x=$(render "$bin" "$tree" "$s")
      echo "$s | $label | ${x:-failed}"
      sum[$label]=$(echo "${sum[$label]:-0} + ${x:-0}" | bc -l)
    done
  done
  cw=$(echo "${sum[cwbvh]} / $ROUNDS" | bc -l)
  b2=$(echo "${sum[bvh2]} / $ROUNDS" | bc -l)
  line=$(printf "%s | mean cwbvh %.4f, bvh2 %.4f M samples/s | cwbvh/bvh2 %.2f" "$s" "$cw" "$b2" "$(echo "$cw / $b2" | bc -l)")
  if [ -n "$BEFORE" ]; then
    bf=$(echo "${sum[before]} / $ROUNDS" | bc -l)
    line+=$(printf " | before %.4f | cwbvh/before %.2f" "$bf" "$(echo "$cw / $bf" | bc -l)")
  fi
  echo "SUMMARY $line"
  unset sum
done
