"""Warm start of the keypoint detector from an exported ONNX model (train_detector.py --init).

The export folds each BatchNorm into its convolution, so the ONNX holds one weight and one bias per
conv. They are read with OpenCV's dnn (the reader the package runs the model with), mapped to the
torch modules by their ONNX scope names, and each folded BatchNorm is rebuilt from the
statistics of its conv's output on training images: running mean and variance as measured, scale
and shift such that the network computes exactly the exported function in eval mode, and nearly
it in train mode (batch statistics instead of running ones).
"""
import torch
import torch.nn as nn


def module_name(onnx_layer):
    """'onnx_node!/s8/s8.1/a/a.0/Conv' -> 's8.1.a.0' (torch scope names repeat the parent's name)."""
    parts = onnx_layer.split("!", 1)[-1].strip("/").split("/")[:-1]
    children, prev = [], None
    for p in parts:
        children.append(p[len(prev) + 1:] if prev is not None and p.startswith(prev + ".") else p)
        prev = p
    return ".".join(children)


def read_onnx_convs(path):
    """{torch module name: (weight, bias)} of the model's convolutions, from OpenCV's dnn."""
    import cv2
    net = cv2.dnn.readNetFromONNX(path)
    out = {}
    for name in net.getLayerNames():
        layer = net.getLayer(net.getLayerId(name))
        if layer.type != "Convolution" or len(layer.blobs) != 2:
            continue  # the output permutation convs have no bias and are fixed buffers here
        w, b = layer.blobs
        out[module_name(name)] = (torch.from_numpy(w.copy()), torch.from_numpy(b.copy()).reshape(-1))
    return out


def load_onnx(net, path):
    """Copies the ONNX convs into net; returns the BatchNorms to calibrate, {bn module: folded bias}."""
    convs = read_onnx_convs(path)
    modules = dict(net.named_modules())
    pending, used = {}, set()
    for name, m in modules.items():
        if not isinstance(m, nn.Conv2d):
            continue
        if name not in convs:
            raise RuntimeError(f"model {path}: no convolution for {name}")
        w, b = convs[name]
        if tuple(w.shape) != tuple(m.weight.shape):
            raise RuntimeError(f"model {path}: {name} has shape {tuple(w.shape)}, the network {tuple(m.weight.shape)}")
        used.add(name)
        with torch.no_grad():
            m.weight.copy_(w)
            if m.bias is not None:
                m.bias.copy_(b)
                continue
            parent, index = name.rsplit(".", 1)
            bn = modules[f"{parent}.{int(index) + 1}"]
            bn.weight.fill_(1.0), bn.bias.copy_(b)
            bn.running_mean.zero_(), bn.running_var.fill_(1.0 - bn.eps)
            pending[bn] = b.clone()
    unused = set(convs) - used
    if unused:
        raise RuntimeError(f"model {path}: convolutions the network does not have: {sorted(unused)}")
    return pending


@torch.no_grad()
def calibrate(net, pending, batches, to_input):
    """Rebuilds the folded BatchNorms from their inputs' statistics over batches (eval function kept)."""
    sums = {bn: [0.0, 0.0, 0] for bn in pending}

    def hook(bn, inputs, _):
        x = inputs[0].double()
        s = sums[bn]
        s[0] = s[0] + x.sum((0, 2, 3))
        s[1] = s[1] + (x * x).sum((0, 2, 3))
        s[2] += x.numel() // x.shape[1]

    handles = [bn.register_forward_hook(hook) for bn in pending]
    net.eval()
    for images, _ in batches:
        net(to_input(images))
    for h in handles:
        h.remove()
    for bn, b in pending.items():
        s0, s1, n = sums[bn]
        mean = s0 / n
        var = (s1 / n - mean * mean).clamp_min(1e-8)
        bn.running_mean.copy_(mean.float()), bn.running_var.copy_(var.float())
        bn.weight.copy_((var + bn.eps).sqrt().float())
        bn.bias.copy_(b + mean.float())
    net.train()
