"""The keypoint detector: a small conv net whose ONNX export emits the YOLOv8-pose layout.

Output (1, 4 + nc + 3K, N): per anchor box centre x, centre y, w, h in input pixels, nc sigmoid
class scores, then K keypoints as (x, y in input pixels, visibility sigmoid). Anchors run over the
strides 8, 16, 32, row-major per level, levels in that order (as ultralytics). The grid and the
strides are decoded inside the graph. Ops: Conv, BatchNormalization (folded), Relu, MaxPool,
Resize (nearest), Concat, Add, Sub, Mul, Exp, Sigmoid, Reshape: OpenCV 4.6 dnn loads it.

Raw head channels per anchor: [box x, box y, k0 x, k0 y, ..., k8 x, k8 y] offsets in stride units
from the anchor centre, [log w, log h] in stride units, [nc class logits, K visibility logits].
"""
import torch
import torch.nn as nn

STRIDES = (8, 16, 32)


def conv(c_in, c_out, k=3, s=1, p=None):
    p = k // 2 if p is None else p
    return nn.Sequential(nn.Conv2d(c_in, c_out, k, s, p, bias=False), nn.BatchNorm2d(c_out), nn.ReLU(inplace=True))


class Block(nn.Module):
    """Two 3x3 convs with a residual connection."""

    def __init__(self, c):
        super().__init__()
        self.a, self.b = conv(c, c), conv(c, c)

    def forward(self, x):
        return x + self.b(self.a(x))


class Head(nn.Module):
    def __init__(self, c_in, c, nc, nk):
        super().__init__()
        self.box = conv(c_in, c)
        self.kpt = conv(c_in, c)
        self.pos_box = nn.Conv2d(c, 2, 1)
        self.pos_kpt = nn.Conv2d(c, 2 * nk, 1)
        self.size = nn.Conv2d(c, 2, 1)
        self.cls = nn.Conv2d(c, nc, 1)
        self.vis = nn.Conv2d(c, nk, 1)
        nn.init.constant_(self.cls.bias, -4.6)  # prior 0.01
        nn.init.constant_(self.size.bias, 1.0)

    def forward(self, x):
        b, k = self.box(x), self.kpt(x)
        pos = torch.cat([self.pos_box(b), self.pos_kpt(k)], 1)
        logits = torch.cat([self.cls(b), self.vis(k)], 1)
        return pos, self.size(b), logits


class KeypointNet(nn.Module):
    def __init__(self, nc=5, nk=9, size=320, width=(24, 32, 48, 96, 128), head=48):
        super().__init__()
        self.nc, self.nk, self.size = nc, nk, size
        c1, c2, c3, c4, c5 = width
        self.stem = nn.Sequential(conv(3, c1, 4, 4, 0), conv(c1, c2))  # stride 4: 4x4 patches
        self.s8 = nn.Sequential(conv(c2, c3, 3, 2), Block(c3))
        self.s16 = nn.Sequential(conv(c3, c4, 3, 2), Block(c4))
        self.s32 = nn.Sequential(conv(c4, c5, 3, 2), Block(c5), conv(c5, c5))
        self.up = nn.Upsample(scale_factor=2, mode="nearest")
        self.top16 = nn.Sequential(conv(c5 + c4, c4, 1), conv(c4, c4))
        self.top8 = nn.Sequential(conv(c4 + c3, c3, 1), conv(c3, c3))
        self.down16 = nn.Sequential(conv(c3, c3, 3, 2))
        self.out16 = nn.Sequential(conv(c3 + c4, c4, 1), conv(c4, c4))
        self.down32 = nn.Sequential(conv(c4, c4, 3, 2))
        self.out32 = nn.Sequential(conv(c4 + c5, c5, 1), conv(c5, c5))
        self.heads = nn.ModuleList([Head(c3, head, nc, nk), Head(c4, head, nc, nk), Head(c5, head, nc, nk)])
        self.decode = False  # True for the export: emit the YOLOv8-pose layout
        w, h = input_size(size)
        for s in STRIDES:
            ys, xs = torch.meshgrid(torch.arange(h // s, dtype=torch.float32), torch.arange(w // s, dtype=torch.float32),
                                    indexing="ij")
            g = torch.stack([xs + 0.5, ys + 0.5]).repeat(1 + nk, 1, 1).unsqueeze(0)  # (1, 2 + 2K, n, n)
            self.register_buffer(f"grid{s}", g, persistent=False)
        self.register_buffer("order", output_order(nc, nk), persistent=False)

    def features(self, x):
        x = self.stem(x)
        p3 = self.s8(x)
        p4 = self.s16(p3)
        p5 = self.s32(p4)
        t4 = self.top16(torch.cat([self.up(p5), p4], 1))
        n3 = self.top8(torch.cat([self.up(t4), p3], 1))
        n4 = self.out16(torch.cat([self.down16(n3), t4], 1))
        n5 = self.out32(torch.cat([self.down32(n4), p5], 1))
        return n3, n4, n5

    def forward(self, x):
        """Training: list per level of (pos, size, logits) raw maps. Export: (1, 4+nc+3K, N)."""
        raw = [h(f) for h, f in zip(self.heads, self.features(x))]
        if not self.decode:
            return raw
        outs = []
        for (pos, size, logits), s in zip(raw, STRIDES):
            xy = (pos + getattr(self, f"grid{s}")) * float(s)
            wh = torch.exp(6.0 - torch.relu(6.0 - size)) * float(s)  # exp(min(size, 6)); OpenCV 4.6 has no Clip(min, max)
            y = torch.cat([xy, wh, torch.sigmoid(logits)], 1)
            y = nn.functional.conv2d(y, self.order)  # channel permutation to the output layout
            outs.append(y.reshape(1, y.shape[1], -1))
        return torch.cat(outs, 2)


def output_order(nc, nk):
    """1x1 conv weights permuting [box xy, kpt xy (2K), wh, cls (nc), vis (K)] to the YOLOv8-pose order."""
    src = {}
    src["bx"], src["by"] = 0, 1
    for k in range(nk):
        src[f"k{k}x"], src[f"k{k}y"] = 2 + 2 * k, 3 + 2 * k
    src["bw"], src["bh"] = 2 + 2 * nk, 3 + 2 * nk
    for c in range(nc):
        src[f"c{c}"] = 4 + 2 * nk + c
    for k in range(nk):
        src[f"k{k}v"] = 4 + 2 * nk + nc + k
    dst = ["bx", "by", "bw", "bh"] + [f"c{c}" for c in range(nc)]
    for k in range(nk):
        dst += [f"k{k}x", f"k{k}y", f"k{k}v"]
    w = torch.zeros(len(dst), len(dst), 1, 1)
    for i, name in enumerate(dst):
        w[i, src[name], 0, 0] = 1.0
    return w


def input_size(size):
    """(width, height) of an input given as one side (square) or as (width, height)."""
    return (size, size) if isinstance(size, int) else tuple(size)


def anchor_centres(size=320):
    """(N, 2) anchor centres in input pixels and (N,) strides, in the output's order."""
    cs, ss = [], []
    w, h = input_size(size)
    for s in STRIDES:
        ys, xs = torch.meshgrid(torch.arange(h // s, dtype=torch.float32), torch.arange(w // s, dtype=torch.float32),
                                indexing="ij")
        cs.append(torch.stack([xs.reshape(-1) + 0.5, ys.reshape(-1) + 0.5], 1) * s)
        ss.append(torch.full((xs.numel(),), float(s)))
    return torch.cat(cs), torch.cat(ss)
