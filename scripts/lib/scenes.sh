# Sourced by the scripts from the repository root, after the release tool is built.
# `split NAME`: the scenes of split NAME in scenes/generated/split.toml.
split() { sed -n "s/^$1 = \[\(.*\)\]/\1/p" scenes/generated/split.toml | tr -d '",'; }
# `render_once SCENE_FILE FRAMES OUT`: renders the scene at 640x360 into OUT, unless OUT already
# holds a dataset.
render_once() {
    [ -f "$3/manifest.json" ] || target/release/patchex render "$1" --frames "$2" \
        --size 640x360 --out "$3"
}
