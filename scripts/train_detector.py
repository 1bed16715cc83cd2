#!/usr/bin/python3
"""Trains the package's keypoint detector on render_dataset output and exports it to ONNX.

  /usr/bin/python3 scripts/train_detector.py --train build/model/train --val build/model/val \
      --minutes 60 --output models/sgt_keypoints.onnx [--checkpoint-dir build/model/checkpoints]

Wall-clock budget (--minutes) with a cosine learning rate over it; a checkpoint each epoch, the
best by validation loss is exported (opset 11, static 1x3x320x320) with models/sgt_keypoints.yaml.
--init MODEL.onnx starts from an exported model instead of random weights (detector_init.py).

  /usr/bin/python3 scripts/train_detector.py --export-only models/sgt_keypoints.onnx --export-size 384x288 \
      --output /tmp/wide.onnx

re-exports a checkpoint (.pt) or an exported model (.onnx + .yaml) for another input size.
"""
import argparse
import itertools
import math
import os
import sys
import time

import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from detector_data import KeypointDataset, collate  # noqa: E402
from detector_export import dataset_names, export, model_names, read_training, write_metadata  # noqa: E402
from detector_init import calibrate, load_onnx  # noqa: E402
from detector_loss import DetectorLoss, decode_boxes, flatten, giou  # noqa: E402
from detector_model import KeypointNet  # noqa: E402

SIZE, NK = 320, 9


def to_input(images):
    return (images.float() / 255.0).contiguous(memory_format=torch.channels_last)


def worker_init(worker_id):
    import numpy as np
    ds = torch.utils.data.get_worker_info().dataset
    ds.rng = np.random.default_rng(torch.initial_seed() % 2**32)


@torch.no_grad()
def evaluate(net, loader, criterion):
    """Mean losses, and per object: hit (best-scoring anchor of its class in its box has IoU > 0.5
    and score > 0.3), mean keypoint error (input px) of hits over visible keypoints."""
    net.eval()
    sums, batches, hits, objects, kerr, kcount = {}, 0, 0, 0, 0.0, 0
    for images, targets in loader:
        raw = net(to_input(images))
        for k, v in criterion(raw, targets).items():
            sums[k] = sums.get(k, 0.0) + float(v)
        batches += 1
        pos, size, logits = flatten(raw)
        boxes = decode_boxes(pos, size, criterion.centres, criterion.strides)
        kp = pos[..., 2:].reshape(*pos.shape[:2], NK, 2) * criterion.strides[None, :, None, None] + criterion.centres[None, :, None]
        scores = torch.sigmoid(logits[..., : net.nc])
        for b, (cls, gt, gkp) in enumerate(targets):
            for j in range(len(cls)):
                objects += 1
                c = criterion.centres
                inside = ((c > gt[j, :2]) & (c < gt[j, 2:])).all(1)
                sc = torch.where(inside, scores[b, :, cls[j]], torch.zeros(()))
                a = int(sc.argmax())
                _, iou = giou(boxes[b, a][None], gt[j][None])
                if float(sc[a]) > 0.3 and float(iou) > 0.5:
                    hits += 1
                    v = gkp[j, :, 2] > 0
                    kerr += float((kp[b, a][v] - gkp[j, v, :2]).norm(dim=1).sum())
                    kcount += int(v.sum())
    net.train()
    out = {k: v / max(batches, 1) for k, v in sums.items()}
    out["recall"] = hits / max(objects, 1)
    out["kpt_px"] = kerr / max(kcount, 1)
    return out


def fmt(d):
    return " ".join(f"{k} {v:.3f}" for k, v in d.items())


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--train")
    ap.add_argument("--val")
    ap.add_argument("--minutes", type=float, default=60.0)
    ap.add_argument("--output", default="models/sgt_keypoints.onnx")
    ap.add_argument("--checkpoint-dir", default="build/model/checkpoints")
    ap.add_argument("--batch", type=int, default=16)
    ap.add_argument("--lr", type=float, default=3e-3)
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--train-size", type=int, default=256,
                    help="training canvas (multiple of 32; smaller is faster; objects keep the scale of the 320 input)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--init", metavar="ONNX", help="start from this exported model (its .yaml beside it) instead of random")
    ap.add_argument("--export-only", metavar="MODEL",
                    help="export MODEL (a .pt checkpoint of this script, or an exported .onnx with its .yaml) and stop")
    ap.add_argument("--export-size", metavar="WxH", default=f"{SIZE}x{SIZE}",
                    help="input size of the --export-only model (default %(default)s; the network is fully convolutional)")
    args = ap.parse_args()
    if args.export_only:
        size = tuple(int(v) for v in args.export_size.lower().split("x"))
        if len(size) != 2 or any(v <= 0 or v % 32 for v in size):
            ap.error(f"--export-size {args.export_size}: width x height, multiples of 32")
        kept = []
        if args.export_only.endswith(".onnx"):
            source_yaml = os.path.splitext(args.export_only)[0] + ".yaml"
            names = model_names(source_yaml)
            net = KeypointNet(len(names), NK, size)
            load_onnx(net, args.export_only)  # eval mode: the folded weights as they are
            training = read_training(source_yaml)
            with open(source_yaml) as f:  # the same weights keep their per-class score thresholds
                kept = [line for line in f if line.startswith(("score_thresholds:", "# score_thresholds:"))]
        else:
            state = torch.load(args.export_only)
            if "names" not in state:
                raise SystemExit(f"{args.export_only}: a checkpoint without class names (older than the catalog's)")
            names = state["names"]
            net = KeypointNet(len(names), NK, size)
            net.load_state_dict(state["model"])
            training = {"checkpoint": args.export_only, "epoch": state["epoch"]}
        export(net, args.output, size)
        yaml_out = os.path.splitext(args.output)[0] + ".yaml"
        write_metadata(yaml_out, size, NK, names, dict(training, exported_from=args.export_only))
        with open(yaml_out, "a") as f:
            f.writelines(kept)
        return
    if not args.train or not args.val:
        ap.error("--train and --val are needed to train")

    names = dataset_names(args.train)
    if dataset_names(args.val) != names:
        raise SystemExit(f"{args.train} and {args.val} name different classes")
    if args.init and model_names(os.path.splitext(args.init)[0] + ".yaml") != names:
        raise SystemExit(f"{args.init} detects other classes than {args.train} holds: {names}")
    torch.set_num_threads(2)
    torch.manual_seed(args.seed)
    train = KeypointDataset(args.train, SIZE, augment=True, seed=args.seed, canvas=args.train_size)
    val = KeypointDataset(args.val, SIZE, augment=False)
    loader = torch.utils.data.DataLoader(train, args.batch, shuffle=True, num_workers=args.workers, collate_fn=collate,
                                         drop_last=True, worker_init_fn=worker_init, persistent_workers=args.workers > 0)
    val_loader = torch.utils.data.DataLoader(val, 32, shuffle=False, num_workers=0, collate_fn=collate)
    net = KeypointNet(len(names), NK, SIZE).to(memory_format=torch.channels_last)
    criterion = DetectorLoss(len(names), NK, args.train_size)
    val_criterion = DetectorLoss(len(names), NK, SIZE)
    init_minutes = 0.0
    if args.init:
        calibrate(net, load_onnx(net, args.init), itertools.islice(loader, 20), to_input)
        init_minutes = float(read_training(os.path.splitext(args.init)[0] + ".yaml").get("total_minutes", 0.0))
        print(f"init: {args.init} ({init_minutes:.1f} min of training before), val {fmt(evaluate(net, val_loader, val_criterion))}",
              flush=True)
    decay = [p for n, p in net.named_parameters() if p.ndim > 1]
    no_decay = [p for n, p in net.named_parameters() if p.ndim <= 1]
    opt = torch.optim.AdamW([{"params": decay, "weight_decay": 5e-4}, {"params": no_decay, "weight_decay": 0.0}], lr=args.lr)
    os.makedirs(args.checkpoint_dir, exist_ok=True)
    print(f"train: {len(train)} images, val: {len(val)}, {sum(p.numel() for p in net.parameters())} parameters, "
          f"budget {args.minutes} min", flush=True)

    budget = args.minutes * 60.0
    start = time.time()
    best, best_path, epoch, step, done = float("inf"), os.path.join(args.checkpoint_dir, "best.pt"), 0, 0, False
    history = []
    while not done:
        epoch += 1
        sums, n, t_epoch = {}, 0, time.time()
        for images, targets in loader:
            frac = (time.time() - start) / budget
            if frac >= 1.0:
                done = True
                break
            warm = min(1.0, (step + 1) / 30.0)
            for g in opt.param_groups:
                g["lr"] = args.lr * warm * (0.03 + 0.97 * 0.5 * (1.0 + math.cos(math.pi * frac)))
            loss = criterion(net(to_input(images)), targets)
            opt.zero_grad(set_to_none=True)
            loss["total"].backward()
            torch.nn.utils.clip_grad_norm_(net.parameters(), 10.0)
            opt.step()
            step += 1
            for k, v in loss.items():
                sums[k] = sums.get(k, 0.0) + float(v)
            n += 1
            if step % 20 == 0:
                print(f"epoch {epoch} step {step} {(time.time() - start) / 60:.1f} min lr {opt.param_groups[0]['lr']:.2e} "
                      f"{fmt({k: v / n for k, v in sums.items()})}", flush=True)
        if n == 0:
            epoch -= 1
            break
        train_loss = {k: v / n for k, v in sums.items()}
        val_loss = evaluate(net, val_loader, val_criterion)
        history.append((epoch, train_loss["total"], val_loss["total"]))
        print(f"== epoch {epoch} ({n} steps, {(time.time() - t_epoch) / 60:.1f} min) train {fmt(train_loss)}\n"
              f"   val {fmt(val_loss)}", flush=True)
        state = {"model": net.state_dict(), "epoch": epoch, "val": val_loss, "train": train_loss, "names": names}
        torch.save(state, os.path.join(args.checkpoint_dir, "last.pt"))
        if val_loss["total"] < best:
            best = val_loss["total"]
            torch.save(state, best_path)
            print(f"   best so far (val loss {best:.4f})", flush=True)

    minutes = (time.time() - start) / 60.0
    state = torch.load(best_path)
    net.load_state_dict(state["model"])
    net = net.to(memory_format=torch.contiguous_format)
    os.makedirs(os.path.dirname(os.path.abspath(args.output)), exist_ok=True)
    export(net, args.output, SIZE)
    write_metadata(os.path.splitext(args.output)[0] + ".yaml", SIZE, NK, names, {
        "images": len(train), "val_images": len(val), "epochs": epoch, "steps": step, "batch": args.batch,
        "train_canvas": args.train_size, "minutes": round(minutes, 1), "init": args.init or "random",
        "total_minutes": round(init_minutes + minutes, 1), "best_epoch": state["epoch"],
        "train_loss": round(state["train"]["total"], 4), "val_loss": round(state["val"]["total"], 4),
        "val_recall": round(state["val"]["recall"], 3), "val_keypoint_px": round(state["val"]["kpt_px"], 2)})
    print(f"done: {epoch} epochs, {step} steps, {minutes:.1f} min; best epoch {state['epoch']} "
          f"train {state['train']['total']:.4f} val {state['val']['total']:.4f}", flush=True)


if __name__ == "__main__":
    main()
