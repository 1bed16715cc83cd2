"""ONNX export of the keypoint detector for OpenCV 4.6 dnn, its checks and its metadata yaml."""
import datetime
import os

import numpy as np
import onnx
import torch



def dataset_names(directory):
    """Class names in label-id order from render_dataset's DIRECTORY/dataset.yaml."""
    import yaml
    with open(os.path.join(directory, "dataset.yaml")) as f:
        names = (yaml.safe_load(f) or {}).get("names")
    if isinstance(names, dict):  # ultralytics style {0: name, 1: name}
        names = [names[k] for k in sorted(names)]
    if not names:
        raise SystemExit(f"{directory}/dataset.yaml names no classes")
    return [str(n) for n in names]


def model_names(metadata_yaml):
    """Class names in output order of an exported model, from its metadata yaml."""
    import yaml
    with open(metadata_yaml) as f:
        names = (yaml.safe_load(f) or {}).get("names")
    if not names:
        raise SystemExit(f"{metadata_yaml} names no classes")
    return [str(n) for n in names]


def drop_identities(model):
    """OpenCV 4.6 cannot parse Identity nodes on initializers (a shared constant): rewire them."""
    g = model.graph
    alias = {n.output[0]: n.input[0] for n in g.node if n.op_type == "Identity"}
    outputs = {o.name for o in g.output}
    if any(k in outputs for k in alias):
        raise RuntimeError("an Identity feeds a graph output")
    keep = [n for n in g.node if n.op_type != "Identity"]
    for n in keep:
        for i, name in enumerate(n.input):
            while name in alias:
                name = alias[name]
            n.input[i] = name
    del g.node[:]
    g.node.extend(keep)
    return model


def export(net, path, size):
    """size: the input's side, or (width, height); the net's grids must have been made for it."""
    from detector_model import input_size
    w, h = input_size(size)
    net = net.eval()
    net.decode = True
    x = torch.rand(1, 3, h, w)
    with torch.no_grad():
        ref = net(x).numpy()
    torch.onnx.export(net, x, path, opset_version=11, do_constant_folding=True, input_names=["images"],
                      output_names=["output0"])
    model = drop_identities(onnx.load(path))
    onnx.checker.check_model(model)
    onnx.save(model, path)
    net.decode = False
    print(f"export: {path} {os.path.getsize(path) / 1e6:.2f} MB, output {ref.shape}, onnx.checker passed", flush=True)
    try:
        import cv2
    except ImportError:
        print("export: python3-opencv missing, OpenCV check left to the C++ side")
        return
    dnn = cv2.dnn.readNetFromONNX(path)
    dnn.setInput(x.numpy())
    out = dnn.forward()
    diff = float(np.abs(out - ref).max())
    print(f"export: cv2.dnn {cv2.__version__} output {out.shape}, max |onnx - torch| = {diff:.2e}", flush=True)
    if out.shape != ref.shape or diff > 1e-2:
        raise RuntimeError("OpenCV's output differs from torch's")


def read_training(path):
    """The training block of a model's metadata yaml; total_minutes counts warm-started runs too."""
    import yaml
    with open(path) as f:
        training = (yaml.safe_load(f) or {}).get("training") or {}
    training.setdefault("total_minutes", training.get("minutes", 0.0))
    return training


def write_metadata(path, size, nk, names, training):
    from detector_model import input_size
    w, h = input_size(size)
    lines = [
        "# Keypoint detector (scripts/train_detector.py). Output (1, 4 + nc + 3K, N) as ultralytics YOLOv8-pose:",
        "# box cx, cy, w, h in input pixels, nc sigmoid scores, K x (x, y in input pixels, visibility sigmoid);",
        "# anchors over strides 8, 16, 32, no NMS. Input: RGB, float = uint8 * scale, no mean, letterboxed",
        "# (centred, pad grey 114). Keypoint pixels are continuous (a pixel's centre at +0.5).",
        f"input_width: {w}",
        f"input_height: {h}",
        f"names: [{', '.join(names)}]",
        f"keypoints: {nk}",
        "keypoint_order: dope_cuboid",
        "letterbox_pad: 114",
        "scale: 0.00392156862745098",
        "swap_rb: false  # the input is RGB",
        "strides: [8, 16, 32]",
        "training:",
    ]
    training = dict({"date": datetime.datetime.utcnow().strftime("%Y-%m-%dT%H:%MZ")}, **training)  # a re-export keeps it
    lines += [f"  {k}: {v}" for k, v in training.items()]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
