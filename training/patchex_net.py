"""The inpainting network of PatchEX: a small U-Net of gated convolutions (Yi et al. 2019,
`sigmoid(conv_g(x)) * elu(conv_f(x))`).

The GPU implementation in `src/network/` runs exactly this topology; the architecture travels
in the safetensors metadata (`widths`), so the two can never disagree about it:

    enc0   gated 3x3, input -> w0
    enc_i  gated 3x3 stride 2, w_{i-1} -> w_i          (i = 1 .. L-1)
    bottle gated 3x3 dilation 2, w_{L-1} -> w_{L-1}
    dec_i  nearest 2x up of the level below, concatenated with enc_i, gated 3x3 -> w_i
    out    plain 3x3, w0 -> 3, added to the input colour (the network learns a correction)

Patches are zero-padded to a multiple of 2^(L-1) by the caller.
"""

import torch
import torch.nn as nn
import torch.nn.functional as F

# Input planes, in the order the GPU packs them (shaders/network_inputs.wgsl).
INPUT_NAMES = ["colour_r", "colour_g", "colour_b", "hole", "roughness", "metallic", "lbp", "zero"]
INPUT_CHANNELS = len(INPUT_NAMES)

FI_WIDTHS = [16, 24, 32]
NEAR_BE_WIDTHS = [8, 16, 16]


class GatedConv(nn.Module):
    def __init__(self, cin, cout, stride=1, dilation=1):
        super().__init__()
        self.feature = nn.Conv2d(cin, cout, 3, stride=stride, padding=dilation, dilation=dilation)
        self.gate = nn.Conv2d(cin, cout, 3, stride=stride, padding=dilation, dilation=dilation)

    def forward(self, x):
        return torch.sigmoid(self.gate(x)) * F.elu(self.feature(x))


class PatchNet(nn.Module):
    """`inputs` planes: the plugin's networks read INPUT_CHANNELS; studies may read more."""

    def __init__(self, widths, inputs=INPUT_CHANNELS):
        super().__init__()
        self.widths = list(widths)
        levels = len(widths)
        self.enc = nn.ModuleList(
            [GatedConv(inputs, widths[0])]
            + [GatedConv(widths[i - 1], widths[i], stride=2) for i in range(1, levels)]
        )
        self.bottle = GatedConv(widths[-1], widths[-1], dilation=2)
        self.dec = nn.ModuleList(
            [GatedConv(widths[i + 1] + widths[i], widths[i]) for i in range(levels - 1)]
        )
        self.out = nn.Conv2d(widths[0], 3, 3, padding=1)
        # The correction starts at zero: an untrained network passes the warp through, and
        # training moves it only as far as the loss gains.
        nn.init.zeros_(self.out.weight)
        nn.init.zeros_(self.out.bias)

    @property
    def multiple(self):
        return 2 ** (len(self.widths) - 1)

    def forward(self, x):
        skips = []
        h = x
        for layer in self.enc:
            h = layer(h)
            skips.append(h)
        h = self.bottle(h)
        for i in reversed(range(len(self.dec))):
            h = F.interpolate(h, scale_factor=2, mode="nearest")
            h = self.dec[i](torch.cat([h, skips[i]], dim=1))
        return x[:, 0:3] + self.out(h)

    def tensors(self):
        """Weights under the names src/network/weights.rs reads."""
        named = {}
        layers = [(f"enc{i}", l) for i, l in enumerate(self.enc)] + [("bottle", self.bottle)]
        layers += [(f"dec{i}", l) for i, l in enumerate(self.dec)]
        for name, layer in layers:
            for part in ("feature", "gate"):
                conv = getattr(layer, part)
                named[f"{name}.{part}.weight"] = conv.weight
                named[f"{name}.{part}.bias"] = conv.bias
        named["out.weight"] = self.out.weight
        named["out.bias"] = self.out.bias
        return {k: v.detach().contiguous().float().cpu() for k, v in named.items()}


def save(net, path, extra=None):
    from safetensors.torch import save_file
    import json

    meta = {"widths": json.dumps(net.widths), "inputs": json.dumps(INPUT_NAMES)}
    meta.update({k: str(v) for k, v in (extra or {}).items()})
    save_file(net.tensors(), path, metadata=meta)
