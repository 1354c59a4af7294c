# Sourced by the training scripts from the repository root: the release tool, PyTorch in
# out/torchenv (about 3 GB, installed once), and scripts/lib/scenes.sh (`split`, `render_once`).
scripts/install-deps.sh python3-venv
cargo build --release -p patchex-cli
if [ ! -x out/torchenv/bin/python ]; then
    python3 -m venv out/torchenv
    out/torchenv/bin/pip install --quiet -r training/requirements.txt
fi
source scripts/lib/scenes.sh
