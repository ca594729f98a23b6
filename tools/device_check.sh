#!/usr/bin/env bash
# The hardware-GPU measurements of issue 15 item 9, as one script for a lent device machine
# (docs/gpu.md "On a hardware GPU"): run where the release binary was copied to `.dev/refract`
# (built on an x86-64 machine: `cargo build --release && mkdir -p .dev && cp
# target/release/refract .dev/ && strip .dev/refract`) and, where the machine lacks the
# Vulkan/EGL loaders, their packages in `.gl/` (see the device notes). Writes everything to
# "$OUT" (default: device-out/): the adapter, one line per measurement, the logs.
#
# Measured: cornell-glass (the default scene, megakernel) at 1920×1080 with 1 spp per
# submission — the viewer's frame — and with 64 spp for throughput; the same with the
# wavefront forced on; env-spheres (wavefront by the rule) both ways; caustic lt+pt and sppm;
# `bench --quick` (CPU) on the machine's cores; `bench --viewer` on the GPU and the CPU.
# Each render prints samples/s and path segments/s; a 1-spp 1080p frame takes
# 2,073,600 / (samples/s) of GPU time (the viewer adds its tone map and the UI).
set -uo pipefail
cd "$(dirname "$0")/.."
OUT="${OUT:-device-out}"
mkdir -p "$OUT"
if [ -d .gl ]; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$(mktemp -d)}"
BIN="${BIN:-.dev/refract}"
[ -x "$BIN" ] || BIN=target/release/refract
nvidia-smi -L >"$OUT/adapter.txt" 2>&1 || true
log="$OUT/measurements.txt"
: >"$log"
run() {
  # run LABEL ENV… -- ARGS…: one render, its summary line appended to the log.
  local label=$1
  shift
  local envs=()
  while [ "$1" != "--" ]; do envs+=("$1"); shift; done
  shift
  local start end line
  start=$(date +%s.%N)
  line=$(env "${envs[@]}" "$BIN" render --device gpu "$@" 2>&1 | tee -a "$OUT/render.log" | grep -E "^wrote|error" | tail -1)
  end=$(date +%s.%N)
  echo "$label | $(echo "$end - $start" | bc) s whole process | $line" | tee -a "$log"
}
# W and H override the resolution (a quick try on lavapipe: W=64 H=36).
size="${W:-1920}x${H:-1080}"
common=(--width "${W:-1920}" --height "${H:-1080}" --out "$OUT/frame.exr")
for wf in off on; do
  # Warm-up compiles the specialisation into the pipeline cache.
  run "cornell-glass warm-up wavefront=$wf" REFRACT_GPU_WAVEFRONT=$wf -- --scene builtin:cornell-glass "${common[@]}" --spp 1
  run "cornell-glass $size 1 spp wavefront=$wf" REFRACT_GPU_WAVEFRONT=$wf -- --scene builtin:cornell-glass "${common[@]}" --spp 1
  run "cornell-glass $size 64 spp wavefront=$wf" REFRACT_GPU_WAVEFRONT=$wf -- --scene builtin:cornell-glass "${common[@]}" --spp 64
  run "env-spheres $size 64 spp wavefront=$wf" REFRACT_GPU_WAVEFRONT=$wf -- --scene builtin:env-spheres "${common[@]}" --spp 64
  run "caustic lt+pt $size 16 spp wavefront=$wf" REFRACT_GPU_WAVEFRONT=$wf -- --scene builtin:caustic --estimator lt+pt "${common[@]}" --spp 16
done
run "caustic sppm $size 16 spp" A=1 -- --scene builtin:caustic --estimator sppm "${common[@]}" --spp 16
# The CPU renderer on that machine's cores, for scale (`bench --quick` is CPU-only).
"$BIN" bench --quick >"$OUT/bench-quick-cpu.txt" 2>&1 || true
# The viewer itself, headless (issue 36): the scripted lecture's edit-to-image latencies,
# compile times, UI frame times, frames/s and samples/s at 1920×1080 and in the default
# window, on the GPU (rendering headless, its image read back, as under glow) and the CPU.
"$BIN" bench --viewer --device gpu --json "$OUT/viewer-gpu.json" >"$OUT/viewer-gpu.log" 2>&1 || true
"$BIN" bench --viewer --device cpu --json "$OUT/viewer-cpu.json" >"$OUT/viewer-cpu.log" 2>&1 || true
