#!/usr/bin/env bash
# `hlod export tiles` checked with the real tools, on the banana sample and the sample city
# (each built by `hlod build`):
#   run_checks.sh gltf-validator HLOD   glTF-Validator reports 0 errors on every GLB
#   run_checks.sh browser HLOD          CesiumJS in headless chromium shows what `hlod play
#                                       --renderer gl` shows from the same camera (view_cesium.mjs)
# Exit 0 pass, 1 fail, 77 skip (node, the npm packages of package.json or chromium absent:
# scripts/install-deps.sh installs them).
set -euo pipefail
check=$1
hlod=$2
here=$(cd "$(dirname "$0")" && pwd)
src=${HLOD_SOURCE_DIR:-$here/../..}
command -v node >/dev/null || { echo "run_checks: node not installed: skipped"; exit 77; }
[ -d "$here/node_modules/gltf-validator" ] || { echo "run_checks: npm packages not installed (scripts/install-deps.sh): skipped"; exit 77; }
if [ "$check" = browser ] && [ ! -x /usr/bin/chromium ]; then echo "run_checks: chromium not installed: skipped"; exit 77; fi

work=$(mktemp -d "${TMPDIR:-/tmp}/hlod-export-checks.XXXXXX")
trap 'rm -rf "$work"' EXIT
origin=37.8716,-122.2727,200   # Berkeley, 200 m above the ellipsoid (clear of the globe)
status=0
for sample in banana city; do
  input=$src/samples/city
  [ "$sample" = banana ] && input=$src/samples/banana/textured_simple_reoriented.obj
  "$hlod" build "$input" -o "$work/$sample.hlod" > "$work/$sample.build.log"
  "$hlod" export tiles "$work/$sample.hlod" -o "$work/$sample-tiles" --origin "$origin"
  case $check in
    gltf-validator)
      node "$here/validate_gltf.mjs" "$work/$sample-tiles" || status=1 ;;
    browser)
      # A still camera at the first key of the sample's walk (close up) and fly (whole model) paths,
      # held long enough for the player's loader to bring in what it selects; frame 60 is compared.
      for kind in walk fly; do
        key=$(grep -v '^#' "$src/samples/$sample/$kind.path" | sed -n 2p)
        read -r _ px py pz qx qy qz qw fov <<< "$key"
        pose="$px $py $pz $qx $qy $qz $qw $fov"
        printf 'hlod-camera-path 1\n0 %s\n1000 %s\n' "$pose" "$pose" > "$work/still.path"
        frames=$work/$sample-$kind-frames
        "$hlod" play "$work/$sample.hlod" --path "$work/still.path" --renderer gl --frames 61 --frames-dir "$frames" \
          --every 60 --width 480 --height 360 > "$work/$sample.play.log"
        echo "$sample, first key of $kind.path:"
        node "$here/view_cesium.mjs" --tileset "$work/$sample-tiles" --origin "$origin" --camera "$pose" \
          --reference "$frames/frame_000060.png" --out "$work/$sample-$kind-cesium.png" --width 480 --height 360 || status=$?
        [ $status = 77 ] && exit 77
        if [ -n "${HLOD_EXPORT_SHOTS:-}" ]; then  # keep the pictures (README figures, debugging)
          mkdir -p "$HLOD_EXPORT_SHOTS"
          cp "$work/$sample-$kind-cesium.png" "$HLOD_EXPORT_SHOTS/"
          cp "$frames/frame_000060.png" "$HLOD_EXPORT_SHOTS/$sample-$kind-play.png"
        fi
      done ;;
  esac
done
exit $status
