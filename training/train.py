"""Trains PatchEX's two inpainting networks on patches written by `patchex patches`.

    python training/train.py --patches out/patches --seed 1 --out assets/networks

Each network learns on the patches of its own region (FI or near-BE) from the training scenes;
the test scenes never reach this script (`--test-scenes` are refused if any patch comes from
one). With `--validation-scenes`, the patches of those scenes are the validation set, apart
from training; otherwise patches are split 80:20 at random (seeded). Each step draws a batch of
16 random 64x64 crops centred on pixels whose result the plugin keeps, flipped left-right at
random. Every epoch is checkpointed (`--resume` goes on from the last), and the weights written
are the epoch with the lowest validation loss; `--patience N` stops after N epochs without a
better one.

The loss follows the paper (section 5.3), over the pixels whose result the plugin keeps, on
Reinhard-tone-mapped colour so that bright pixels do not drown the rest: L1 over them + 0.5 L1
over their holes + 0.5 L1 over their valid pixels + 0.1 perceptual (feature L1) + 0.01 style
(Gram-matrix L1); `--no-perceptual` drops the last two (the paper's ablation). The kept pixels
are the patch's region for the paper's blend (`--every-pixel`); by default they are the region's
holes, since the plugin's default blend keeps a correction only there
(`PatchexNetworkSettings.correct_valid_pixels`). The perceptual and style terms use VGG-16's first
three blocks when `--vgg16 PATH` names a file of its ImageNet weights (a PyTorch state dict with
torchvision's `features.N.weight` names); otherwise a fixed, seeded, randomly initialised
network of the same shape (random-feature perceptual loss): no download is needed, and the
manifest says which was used.

Writes fi.safetensors, near_be.safetensors (the networks, with their metadata), manifest.json
(data, seed, epochs, final losses) and loss_curve.png into --out.
"""

import argparse
import glob
import json
import math
import os
import random
import time

import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F
from safetensors.numpy import load_file
from safetensors import safe_open

from patchex_net import FI_WIDTHS, NEAR_BE_WIDTHS, PatchNet, save

CROP = 64
BATCH = 16
NETWORKS = {"fi": FI_WIDTHS, "near_be": NEAR_BE_WIDTHS}


def tone_map(x):
    return x / (1.0 + x.abs())


class Features(nn.Module):
    """VGG-16's first three blocks (pool1, pool2, pool3 outputs), frozen."""

    CONFIG = [64, 64, "M", 128, 128, "M", 256, 256, 256, "M"]

    def __init__(self, scale=1):
        super().__init__()
        layers, cin = [], 3
        for v in self.CONFIG:
            if v == "M":
                layers.append(nn.MaxPool2d(2))
            else:
                layers += [nn.Conv2d(cin, v // scale, 3, padding=1), nn.ReLU(inplace=False)]
                cin = v // scale
        self.features = nn.Sequential(*layers)
        for p in self.parameters():
            p.requires_grad_(False)

    def forward(self, x):
        outs = []
        for layer in self.features:
            x = layer(x)
            if isinstance(layer, nn.MaxPool2d):
                outs.append(x)
        return outs


def feature_network(vgg16_path):
    if vgg16_path:
        net = Features()
        state = torch.load(vgg16_path, map_location="cpu")
        mine = {k: v for k, v in state.items() if k.startswith("features.") and k in net.state_dict()}
        if len(mine) != len(net.state_dict()):
            raise SystemExit(f"{vgg16_path}: not VGG-16 weights with torchvision's names")
        net.load_state_dict(mine)
        mean = torch.tensor([0.485, 0.456, 0.406]).view(1, 3, 1, 1)
        std = torch.tensor([0.229, 0.224, 0.225]).view(1, 3, 1, 1)
        return net.eval(), mean, std, f"VGG-16 ImageNet weights from {os.path.basename(vgg16_path)}"
    # A quarter of VGG-16's widths keeps the CPU cost down; fixed seed 0, independent of --seed.
    generator = torch.Generator().manual_seed(0)
    net = Features(scale=4)
    for m in net.modules():
        if isinstance(m, nn.Conv2d):
            nn.init.kaiming_normal_(m.weight, generator=generator)
            nn.init.zeros_(m.bias)
    return net.eval(), torch.zeros(1, 3, 1, 1), torch.ones(1, 3, 1, 1), (
        "random-feature substitute: VGG-16's first three blocks at a quarter width, "
        "Kaiming-initialised with seed 0, frozen (no VGG-16 weights were given)"
    )


def gram(f):
    b, c, h, w = f.shape
    f = f.reshape(b, c, h * w)
    return f @ f.transpose(1, 2) / (c * h * w)


class Loss:
    def __init__(self, features, mean, std, perceptual_weights, every_pixel):
        self.features, self.mean, self.std = features, mean, std
        self.perceptual_weight, self.style_weight = perceptual_weights
        self.every_pixel = every_pixel

    def __call__(self, output, target, region, hole):
        if not self.every_pixel:
            region = region * hole
        out, tgt = tone_map(output), tone_map(target)
        diff = (out - tgt).abs().mean(1, keepdim=True)
        eps = 1.0
        l1 = (diff * region).sum() / (region.sum() + eps)
        holes = region * hole
        valid = region * (1 - hole)
        l1_hole = (diff * holes).sum() / (holes.sum() + eps)
        l1_valid = (diff * valid).sum() / (valid.sum() + eps)
        # Perceptual terms on the composite: the network's result inside the region, the truth
        # outside it, as the plugin's blend composes them.
        comp = region * out + (1 - region) * tgt
        fc = self.features((comp - self.mean) / self.std)
        ft = self.features((tgt - self.mean) / self.std)
        perceptual = sum((a - b).abs().mean() for a, b in zip(fc, ft))
        style = sum((gram(a) - gram(b)).abs().mean() for a, b in zip(fc, ft))
        total = l1 + 0.5 * l1_hole + 0.5 * l1_valid
        total = total + self.perceptual_weight * perceptual + self.style_weight * style
        parts = {"l1": l1, "hole": l1_hole, "valid": l1_valid, "perceptual": perceptual, "style": style}
        return total, {k: v.item() for k, v in parts.items()}


def load_patches(folder, network, test_scenes, every_pixel):
    patches = []
    for path in sorted(glob.glob(os.path.join(folder, f"*_{network}.safetensors"))):
        with safe_open(path, "np") as f:
            meta = f.metadata()
        if meta["dataset"] in test_scenes:
            raise SystemExit(f"{path} comes from test scene {meta['dataset']}: keep it out of training")
        t = load_file(path)
        kept = t["region"][0] if every_pixel else t["region"][0] * t["hole"][0]
        if kept.sum() == 0:
            continue
        patches.append(
            {
                "input": t["input"],
                "target": t["target"],
                "region": t["region"],
                "hole": t["hole"],
                "centres": np.argwhere(kept > 0),
                "dataset": meta["dataset"],
            }
        )
    if not patches:
        raise SystemExit(f"no {network} patches in {folder}")
    return patches


def crop(patch, rng):
    """A CROP x CROP window centred on a random pixel of the region, zero past the patch."""
    cy, cx = patch["centres"][rng.randrange(len(patch["centres"]))]
    _, h, w = patch["input"].shape
    y0, x0 = cy - CROP // 2, cx - CROP // 2
    out = []
    for name in ("input", "target", "region", "hole"):
        src = patch[name]
        dst = np.zeros((src.shape[0], CROP, CROP), np.float32)
        ys, xs = max(y0, 0), max(x0, 0)
        ye, xe = min(y0 + CROP, h), min(x0 + CROP, w)
        dst[:, ys - y0 : ye - y0, xs - x0 : xe - x0] = src[:, ys:ye, xs:xe]
        out.append(dst)
    if rng.random() < 0.5:
        out = [a[:, :, ::-1].copy() for a in out]
    return out


def batch(patches, rng, size=BATCH):
    crops = [crop(patches[rng.randrange(len(patches))], rng) for _ in range(size)]
    return [torch.from_numpy(np.stack(parts)) for parts in zip(*crops)]


def split(patches, args):
    """Training and validation patches: by scene with --validation-scenes, else 80:20 at random."""
    if args.validation_scenes:
        scenes = set(args.validation_scenes.split(","))
        training = [p for p in patches if p["dataset"] not in scenes]
        validation = [p for p in patches if p["dataset"] in scenes]
        if not training or not validation:
            raise SystemExit(f"--validation-scenes {args.validation_scenes} leaves a split empty")
        return training, validation
    order = list(range(len(patches)))
    random.Random(args.seed).shuffle(order)
    cut = max(1, int(round(0.8 * len(order))))
    training = [patches[i] for i in order[:cut]]
    return training, [patches[i] for i in order[cut:]] or training[:1]


def validation_batches(validation, args):
    """A fixed validation set: the same crops every epoch."""
    val_rng = random.Random(args.seed + 1)
    return [batch(validation, val_rng) for _ in range(args.val_batches)]


def train(network, patches, args, loss_fn, log):
    torch.manual_seed(args.seed)
    rng = random.Random(args.seed)
    training, validation = split(patches, args)
    val_batches = validation_batches(validation, args)

    net = PatchNet(NETWORKS[network])
    optimiser = torch.optim.Adam(net.parameters(), lr=args.lr)
    curve, best, first = [], None, 1
    checkpoint = os.path.join(args.out, f"checkpoint_{network}.pt")
    if args.resume and os.path.exists(checkpoint):
        state = torch.load(checkpoint, weights_only=False)
        net.load_state_dict(state["net"])
        optimiser.load_state_dict(state["optimiser"])
        curve, best, first = state["curve"], state["best"], state["epoch"] + 1
        rng.setstate(state["rng"])
        torch.set_rng_state(state["torch_rng"])
        log(f"{network}: resumed after epoch {state['epoch']}")
    for epoch in range(first, args.epochs + 1):
        if best and epoch - best["epoch"] > args.patience:
            log(f"{network}: no better validation loss for {args.patience} epochs, stopping")
            break
        net.train()
        train_total = 0.0
        for _ in range(args.steps):
            x, y, region, hole = batch(training, rng)
            loss, _ = loss_fn(net(x), y, region, hole)
            optimiser.zero_grad()
            loss.backward()
            optimiser.step()
            train_total += float(loss)
        net.eval()
        with torch.no_grad():
            val = [loss_fn(net(x), y, r, h) for x, y, r, h in val_batches]
        val_total = sum(float(v[0]) for v in val) / len(val)
        parts = {k: sum(v[1][k] for v in val) / len(val) for k in val[0][1]}
        curve.append({"epoch": epoch, "train": train_total / args.steps, "validation": val_total, **parts})
        log(f"{network} epoch {epoch}/{args.epochs}: train {train_total / args.steps:.4f}, validation {val_total:.4f} {parts}")
        if best is None or val_total < best["validation"]:
            best = {"epoch": epoch, "validation": val_total, "net": {k: v.clone() for k, v in net.state_dict().items()}}
        torch.save(
            {"net": net.state_dict(), "optimiser": optimiser.state_dict(), "curve": curve, "best": best,
             "epoch": epoch, "rng": rng.getstate(), "torch_rng": torch.get_rng_state()},
            checkpoint,
        )
    net.load_state_dict(best["net"])
    return net, curve, best["epoch"], len(training), len(validation)


def warp_only_validation(patches, args, loss_fn):
    """The loss of passing the warped colour through unchanged: what the network must beat."""
    _, validation = split(patches, args)
    losses = [float(loss_fn(x[:, 0:3], y, r, h)[0]) for x, y, r, h in validation_batches(validation, args)]
    return sum(losses) / len(losses)


def plot(curves, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    for network, curve in curves.items():
        epochs = [c["epoch"] for c in curve]
        ax.plot(epochs, [c["train"] for c in curve], label=f"{network} training")
        ax.plot(epochs, [c["validation"] for c in curve], "--", label=f"{network} validation")
    ax.set_xlabel("epoch")
    ax.set_ylabel("loss")
    ax.set_title("PatchEX inpainting networks")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--patches", required=True, help="folder written by `patchex patches`")
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--epochs", type=int, default=10)
    parser.add_argument("--steps", type=int, default=40, help="batches per epoch")
    parser.add_argument("--val-batches", type=int, default=8)
    parser.add_argument("--lr", type=float, default=2e-3)
    parser.add_argument("--vgg16", help="VGG-16 ImageNet state dict for the perceptual terms")
    parser.add_argument("--test-scenes", default="crossing_street,fast_run")
    parser.add_argument("--validation-scenes", help="scenes whose patches are the validation set")
    parser.add_argument("--patience", type=int, default=1000, help="epochs without a better validation loss before stopping")
    parser.add_argument("--resume", action="store_true", help="go on from the checkpoints in --out")
    parser.add_argument(
        "--every-pixel",
        action="store_true",
        help="train for the paper's blend: the loss over the whole region, not only its holes",
    )
    parser.add_argument("--networks", default="fi,near_be")
    parser.add_argument(
        "--no-perceptual",
        action="store_true",
        help="drop the perceptual and style terms (the paper's ablation); still reported",
    )
    args = parser.parse_args()

    torch.set_num_threads(max(1, os.cpu_count() or 1))
    torch.use_deterministic_algorithms(True)
    os.makedirs(args.out, exist_ok=True)
    test_scenes = set(filter(None, args.test_scenes.split(",")))
    features, mean, std, perceptual_name = feature_network(args.vgg16)
    perceptual_weights = (0.0, 0.0) if args.no_perceptual else (0.1, 0.01)
    loss_fn = Loss(features, mean, std, perceptual_weights, args.every_pixel)
    started = time.time()
    manifest = {
        "command": "python training/train.py " + " ".join(
            f"--{k.replace('_', '-')}" if v is True else f"--{k.replace('_', '-')} {v}"
            for k, v in vars(args).items()
            if v is not None and v is not False
        ),
        "seed": args.seed,
        "epochs": args.epochs,
        "steps_per_epoch": args.steps,
        "batch": BATCH,
        "crop": CROP,
        "learning_rate": args.lr,
        "perceptual": perceptual_name,
        "loss_weights": {"l1": 1.0, "hole": 0.5, "valid": 0.5, "perceptual": perceptual_weights[0], "style": perceptual_weights[1]},
        "test_scenes": sorted(test_scenes),
        "validation_scenes": sorted(filter(None, (args.validation_scenes or "").split(","))),
        "kept_pixels": "the region" if args.every_pixel else "the region's holes",
        "networks": {},
    }
    curves = {}
    for network in args.networks.split(","):
        patches = load_patches(args.patches, network, test_scenes, args.every_pixel)
        baseline = warp_only_validation(patches, args, loss_fn)
        net, curve, best_epoch, n_train, n_val = train(network, patches, args, loss_fn, print)
        final = curve[best_epoch - 1]
        manifest["networks"][network] = {
            "widths": NETWORKS[network],
            "training_scenes": sorted({p["dataset"] for p in split(patches, args)[0]}),
            "patches": {"training": n_train, "validation": n_val},
            "best_epoch": best_epoch,
            "epochs_run": len(curve),
            "final_losses": final,
            "validation_loss_of_the_warp_alone": baseline,
        }
        save(net, os.path.join(args.out, f"{network}.safetensors"), {"seed": args.seed, "epochs": best_epoch})
        curves[network] = curve
    manifest["seconds"] = round(time.time() - started)
    with open(os.path.join(args.out, "manifest.json"), "w") as f:
        json.dump(manifest, f, indent=2)
    plot(curves, os.path.join(args.out, "loss_curve.png"))
    print(json.dumps({k: v["final_losses"]["validation"] for k, v in manifest["networks"].items()}))


if __name__ == "__main__":
    main()
