# Sourced by the training scripts from the repository root: the release tool, PyTorch in
# out/torchenv (about 3 GB, installed once), and `split NAME` for a split's scenes.
scripts/install-deps.sh python3-venv
cargo build --release -p patchex-cli
if [ ! -x out/torchenv/bin/python ]; then
    python3 -m venv out/torchenv
    out/torchenv/bin/pip install --quiet -r training/requirements.txt
fi
split() { sed -n "s/^$1 = \[\(.*\)\]/\1/p" scenes/generated/split.toml | tr -d '",'; }
