"""Golden tensors for the GPU inference's parity test (tests/network.rs): a seeded input patch
and PyTorch's output for a network, either trained (--weights) or a small one with seeded
random weights (--save-weights writes them).

    python training/export_golden.py --save-weights tests/fixtures/network/tiny.safetensors \
        --out tests/fixtures/network/tiny_golden.safetensors
    python training/export_golden.py --weights assets/networks/fi.safetensors \
        --out tests/fixtures/network/fi_golden.safetensors
"""

import argparse
import json

import torch
from safetensors.torch import load_file, save_file
from safetensors import safe_open

from patchex_net import INPUT_CHANNELS, PatchNet, save


def golden_input(size, seed):
    g = torch.Generator().manual_seed(seed)
    x = torch.rand(1, INPUT_CHANNELS, size, size, generator=g)
    x[:, 3] = (x[:, 3] > 0.7).float()  # hole mask
    x[:, 7] = 0.0  # the padding plane
    x[:, 0:3] *= 1.0 - x[:, 3:4]  # holes carry no colour
    return x


def load_net(path):
    with safe_open(path, "pt") as f:
        widths = json.loads(f.metadata()["widths"])
    net = PatchNet(widths)
    tensors = load_file(path)
    state = {}
    for key, value in net.state_dict().items():
        # state_dict names (enc.0.feature.weight) map onto tensors() names (enc0.feature.weight).
        state[key] = tensors[to_export_name(key)]
    net.load_state_dict(state)
    return net


def to_export_name(key):
    parts = key.split(".")
    if parts[0] in ("enc", "dec"):
        return f"{parts[0]}{parts[1]}." + ".".join(parts[2:])
    return key


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--weights")
    parser.add_argument("--save-weights")
    parser.add_argument("--size", type=int, default=16)
    parser.add_argument("--seed", type=int, default=7)
    args = parser.parse_args()
    torch.manual_seed(args.seed)
    if args.weights:
        net = load_net(args.weights)
    else:
        net = PatchNet([4, 8, 8])
        save(net, args.save_weights, {"seed": args.seed})
    net.eval()
    x = golden_input(args.size, args.seed)
    with torch.no_grad():
        y = net(x)
    tensors = {"input": x[0].contiguous(), "output": y[0].contiguous()}
    save_file(tensors, args.out, metadata={"widths": json.dumps(net.widths), "seed": str(args.seed)})
    print(f"{args.out}: widths {net.widths}, input {tuple(x.shape)}, output mean {y.mean():.4f}")


if __name__ == "__main__":
    main()
