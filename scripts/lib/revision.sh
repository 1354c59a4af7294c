# Builds revision $1 (committed work only) in a git worktree under out/compare_builds, whose
# target folder is kept between runs, and sets `before_tool` to its patchex CLI. The worktree is
# removed when the calling script exits. Source it from a script that runs in the repository root.
build_revision() {
    local rev=$1 out=out/compare_builds
    local worktree=$out/worktree
    rm -rf "$worktree"
    git worktree prune
    git worktree add --detach "$worktree" "$rev" >/dev/null
    trap 'git worktree remove --force "'"$worktree"'"' EXIT
    CARGO_TARGET_DIR="$PWD/$out/target" cargo build --release -p patchex -p patchex-cli \
        --manifest-path "$worktree/Cargo.toml"
    before_tool=$out/target/release/patchex
}
