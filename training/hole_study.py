"""Can a network repair the warp's holes wherever they are, and what must it read to do so?

    python training/hole_study.py --samples out/patches_holes --test-samples out/patches_holes_test \
        --seed 1 --out out/hole_study

A study, not a network the plugin runs: the plugin's networks see only the patches
around dynamic objects, and most holes lie outside them. It reads the whole-frame samples that
`patchex patches --holes` writes and trains, with the same seed, data and steps, one network per
input set:

- `paper`: the planes the plugin's networks read (warped colour, hole, roughness, metallic, LBP);
- `gbuffer`: those, plus what the target's G-buffer knows about the uncovered surface: its
  normal, a depth-edge mask (largest log-depth step to a neighbour) and the warp's best
  agreement.

Each network is the FI network's U-Net (`FI_WIDTHS`, the topology the plugin's code generator
runs) with that many input planes, trained on 64x64 crops centred on the training scenes' holes
(L1 over the holes of Reinhard-tone-mapped colour, Adam, batch 16). Every `--every` steps it is
scored over the validation scenes' whole frames; the best score is kept and `--patience`
evaluations without a better one stop it. Only then are the test scenes scored, once.

The score is PSNR over the hole pixels of the remodulated colour, tone-mapped as `patchex eval`
does (Reinhard, then sRGB), against the rendered target: the warp's fill beside the network's
result, pooled and per scene. Writes results.json and results.md into --out.
"""

import argparse
import glob
import json
import os
import random
import time

import numpy as np
import torch
from safetensors import safe_open
from safetensors.numpy import load_file

from patchex_net import FI_WIDTHS, INPUT_NAMES, PatchNet

CROP = 64
BATCH = 16
# The plugin's input planes, less the zero plane that pads them to eight.
PAPER_PLANES = [i for i, name in enumerate(INPUT_NAMES) if name != "zero"]
# `guide` planes written by `patchex patches --holes`.
NORMAL, DEPTH, AGREEMENT, MODULATION = slice(0, 3), 3, 4, slice(5, 8)


def depth_edges(depth):
    """Largest log-depth step from each pixel to its four neighbours, x10, at most 1."""
    log_depth = np.log(np.maximum(depth, 1e-3))
    padded = np.pad(log_depth, 1, mode="edge")
    steps = [np.abs(log_depth - padded[1 + dy : 1 + dy + depth.shape[0], 1 + dx : 1 + dx + depth.shape[1]])
             for dy, dx in ((-1, 0), (1, 0), (0, -1), (0, 1))]
    return np.minimum(10.0 * np.maximum.reduce(steps), 1.0)


def load(path, inputs):
    t = load_file(path)
    with safe_open(path, "np") as f:
        dataset = f.metadata()["dataset"]
    guide = t["guide"]
    x = t["input"][PAPER_PLANES]
    if inputs == "gbuffer":
        x = np.concatenate([x, guide[NORMAL], depth_edges(guide[DEPTH])[None], guide[AGREEMENT : AGREEMENT + 1]])
    hole = t["hole"]
    return {"x": x, "y": t["target"], "hole": hole, "modulation": guide[MODULATION], "dataset": dataset,
            "centres": np.argwhere(hole[0] > 0)}


def tone_map(x):
    return x / (1.0 + x.abs())


def displayed(shading, modulation):
    """Remodulated, Reinhard-tone-mapped, sRGB-encoded colour, as `patchex eval` scores it."""
    c = np.maximum(shading * modulation, 0.0)
    c = np.clip(c / (1.0 + c), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def crop(sample, rng):
    cy, cx = sample["centres"][rng.randrange(len(sample["centres"]))]
    _, h, w = sample["x"].shape
    y0 = min(max(cy - CROP // 2, 0), h - CROP)
    x0 = min(max(cx - CROP // 2, 0), w - CROP)
    parts = [sample[k][:, y0 : y0 + CROP, x0 : x0 + CROP] for k in ("x", "y", "hole")]
    if rng.random() < 0.5:
        parts = [p[:, :, ::-1] for p in parts]
    return [np.ascontiguousarray(p) for p in parts]


def score(net, samples):
    """Squared error over holes of the warp's fill and the network's result, pooled and per scene."""
    per_scene = {}
    net.eval()
    with torch.no_grad():
        for s in samples:
            hole = s["hole"][0] > 0
            if not hole.any():
                continue
            _, h, w = s["x"].shape
            m = net.multiple
            x = np.zeros((1, s["x"].shape[0], -(-h // m) * m, -(-w // m) * m), np.float32)
            x[0, :, :h, :w] = s["x"]
            out = net(torch.from_numpy(x))[0, :, :h, :w].numpy()
            truth = displayed(s["y"], s["modulation"])
            errors = [((displayed(c, s["modulation"]) - truth) ** 2)[:, hole].sum() for c in (s["x"][0:3], out)]
            tally = per_scene.setdefault(s["dataset"], [0.0, 0.0, 0])
            tally[0] += errors[0]
            tally[1] += errors[1]
            tally[2] += 3 * int(hole.sum())
    net.train()
    psnr = lambda e, n: float(10 * np.log10(n / max(e, 1e-12)))
    scenes = {k: {"warp": psnr(v[0], v[2]), "network": psnr(v[1], v[2]), "hole_pixels": v[2] // 3}
              for k, v in sorted(per_scene.items())}
    pooled = [sum(v[i] for v in per_scene.values()) for i in range(3)]
    return {"warp": psnr(pooled[0], pooled[2]), "network": psnr(pooled[1], pooled[2]), "scenes": scenes}


def study(inputs, samples, args, log):
    split = {k: set(v) for k, v in args.split.items()}
    training = [s for s in samples if s["dataset"] in split["training"] and len(s["centres"])]
    validation = [s for s in samples if s["dataset"] in split["validation"]]
    torch.manual_seed(args.seed)
    rng = random.Random(args.seed)
    net = PatchNet(FI_WIDTHS, inputs=training[0]["x"].shape[0])
    optimiser = torch.optim.Adam(net.parameters(), lr=args.lr)
    best = {"step": 0, "validation": score(net, validation), "state": {k: v.clone() for k, v in net.state_dict().items()}}
    log(f"{inputs}: warp alone {best['validation']['warp']:.3f} dB over the validation holes")
    waited, started = 0, time.time()
    for step in range(1, args.steps + 1):
        x, y, hole = [torch.from_numpy(np.stack(p)) for p in zip(*(crop(training[rng.randrange(len(training))], rng) for _ in range(BATCH)))]
        diff = (tone_map(net(x)) - tone_map(y)).abs().mean(1, keepdim=True)
        loss = (diff * hole).sum() / (hole.sum() + 1.0)
        optimiser.zero_grad()
        loss.backward()
        optimiser.step()
        if step % args.every == 0:
            validation_score = score(net, validation)
            log(f"{inputs} step {step} ({time.time() - started:.0f} s): loss {loss.item():.4f}, "
                f"validation holes {validation_score['network']:.3f} dB")
            if validation_score["network"] > best["validation"]["network"]:
                best = {"step": step, "validation": validation_score,
                        "state": {k: v.clone() for k, v in net.state_dict().items()}}
                waited = 0
            else:
                waited += 1
                if waited >= args.patience:
                    log(f"{inputs}: no better validation score in {args.patience} evaluations, stopping")
                    break
    net.load_state_dict(best["state"])
    return {"inputs": inputs, "planes": training[0]["x"].shape[0], "best_step": best["step"],
            "seconds": round(time.time() - started), "validation": best["validation"]}, net


def table(title, results, which):
    scenes = sorted(results[0][which]["scenes"])
    lines = [f"### {title}", "", "| scenes | hole pixels | warp's fill | " + " | ".join(f"network, {r['inputs']} inputs" for r in results) + " |",
             "|---|---|---|" + "---|" * len(results)]
    first = results[0][which]
    def row(name, pixels, pick):
        cells = [f"{pick(r)['network']:.2f} ({pick(r)['network'] - pick(r)['warp']:+.2f})" for r in results]
        return f"| {name} | {pixels} | {pick(results[0])['warp']:.2f} | " + " | ".join(cells) + " |"
    lines.append(row("pooled", sum(v["hole_pixels"] for v in first["scenes"].values()), lambda r: r[which]))
    for scene in scenes:
        lines.append(row(scene, first["scenes"][scene]["hole_pixels"], lambda r, s=scene: r[which]["scenes"][s]))
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--samples", required=True, help="`patchex patches --holes` output of the training and validation scenes")
    parser.add_argument("--test-samples", required=True, help="the same for the test scenes, scored once at the end")
    parser.add_argument("--split", default=os.path.join(os.path.dirname(__file__), "..", "scenes", "generated", "split.toml"))
    parser.add_argument("--seed", type=int, required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--steps", type=int, default=3000)
    parser.add_argument("--every", type=int, default=250, help="steps between validation scores")
    parser.add_argument("--patience", type=int, default=3)
    parser.add_argument("--lr", type=float, default=1e-3)
    parser.add_argument("--inputs", default="paper,gbuffer")
    args = parser.parse_args()
    with open(args.split) as f:
        lines = [line.split("=", 1) for line in f if "=" in line and not line.startswith("#")]
    args.split = {key.strip(): json.loads(value) for key, value in lines}
    torch.set_num_threads(max(1, os.cpu_count() or 1))
    torch.use_deterministic_algorithms(True)
    os.makedirs(args.out, exist_ok=True)
    results = []
    for inputs in args.inputs.split(","):
        samples = [load(p, inputs) for p in sorted(glob.glob(os.path.join(args.samples, "*_holes.safetensors")))]
        if any(s["dataset"] in args.split["test"] for s in samples):
            raise SystemExit(f"{args.samples} holds test scenes: keep them in --test-samples")
        result, net = study(inputs, samples, args, lambda m: print(m, flush=True))
        del samples
        tests = [load(p, inputs) for p in sorted(glob.glob(os.path.join(args.test_samples, "*_holes.safetensors")))]
        result["test"] = score(net, tests)
        print(f"{inputs}: test holes {result['test']['warp']:.3f} -> {result['test']['network']:.3f} dB", flush=True)
        results.append(result)
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump({"command": "python training/hole_study.py " + " ".join(f"--{k.replace('_', '-')} {v}" for k, v in vars(args).items() if k != "split"),
                   "results": results}, f, indent=2)
    with open(os.path.join(args.out, "results.md"), "w") as f:
        f.write("PSNR in dB over the holes of the remodulated, tone-mapped colour (in brackets: against the warp's fill).\n\n")
        f.write(table("Validation scenes (where the step was chosen)", results, "validation") + "\n")
        f.write(table("Test scenes (scored once, after the choice)", results, "test"))
        steps = ", ".join(f"{r['inputs']}: step {r['best_step']}, {r['seconds']} s" for r in results)
        f.write(f"\nBest validation step and training time: {steps}.\n")


if __name__ == "__main__":
    main()
