# Sourced by the scripts that make the published results: `publish FROM TO` copies a file a run
# wrote into docs/results/ under the name the guides link to.
publish() {
    mkdir -p docs/results
    cp "$1" "docs/results/$2"
}
