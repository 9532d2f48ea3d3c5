#!/usr/bin/env bash
# The main job end to end on the bundled warehouse, offline, with the small in-process model.
# Called by `make demo`; every output lands in $1 (default demo_out/).
set -euo pipefail
OUT=${1:-demo_out}
SNG=".venv/bin/socnavgen"
LOC=examples/locations/warehouse
mkdir -p "$OUT"
step() { printf '\n\033[1;36m== %s ==\033[0m\n' "$*"; }

step "1. Check the bundled location and render its annotated map"
$SNG location check "$LOC"
$SNG location show "$LOC" -o "$OUT/warehouse_annotated.png"

step "2. Generate a scenario with the in-process SmolLM2-135M model (offline; --llm openai:gpt-4o for a real model)"
rm -rf "$OUT/run"
$SNG generate --location "$LOC" \
  --context "Delivery robot in a small warehouse; employees walk around doing their daily duties" \
  --task "Transport a box from one point to another" \
  --rough "The robot turns at a blind corner and meets a human who stops until the robot is not blocking it anymore" \
  --llm local --out "$OUT/run"

step "3. Export it for HuNavSim (SocRATES fork and upstream 2.x)"
$SNG export "$OUT/run" --format socrates -o "$OUT/export_socrates"
$SNG export "$OUT/run" --format hunav2 -o "$OUT/export_hunav2" || echo "(hunav2 refused this run: the nodes listed above have no 2.x equivalent)"

step "4. Simulate it headless (the robot plays the scenario's script), with metrics and an animation"
$SNG simulate "$OUT/run" --gif

step "5. Verify that the intended interaction happens"
$SNG verify "$OUT/run" || echo "(the 135M smoke-test model proves the plumbing, not scenario quality: see the findings above)"

step "6. A scenario card, instantiated deterministically (no LLM), simulated and verified"
rm -rf "$OUT/card_intersection_wait"
$SNG cards generate intersection-wait --location "$LOC" -o "$OUT/card_intersection_wait"
$SNG export "$OUT/card_intersection_wait" --format socrates -o "$OUT/card_intersection_wait/export_socrates"
$SNG simulate "$OUT/card_intersection_wait" --gif
$SNG verify "$OUT/card_intersection_wait"

step "7. Another card exported for upstream HuNavSim 2.x (BT.CPP v4, nodes translated)"
rm -rf "$OUT/card_frontal_approach"
$SNG cards generate frontal-approach --location "$LOC" -o "$OUT/card_frontal_approach"
$SNG export "$OUT/card_frontal_approach" --format hunav2 -o "$OUT/card_frontal_approach/export_hunav2"

step "8. A small campaign: 3 cards x 3 robots (scripted, sfm, straight) x 3 seeds, and its report"
rm -rf "$OUT/campaign"
$SNG campaign run examples/campaigns/demo.yaml -o "$OUT/campaign"
$SNG campaign report "$OUT/campaign"

step "Done: outputs in $OUT/"
find "$OUT" -maxdepth 3 -type f | sort | head -60
