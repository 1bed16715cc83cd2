"""Anchor assignment and losses of the keypoint detector.

Assignment (anchor-free, centre sampling): a ground-truth object goes to the pyramid levels its
size fits (longest side of its visible box in input pixels: stride 8 below 64 px, 16 for 32-160,
32 from 96 up); there its positives are the anchors whose centres lie inside the box and within
1.5 strides of the box centre, plus always the anchor nearest to the centre. An anchor claimed by
several objects takes the smallest. Losses, normalised by the number of positives: BCE for the
classes (all anchors), GIoU + L1 (stride units) for the boxes, L1 in stride units for the
keypoints weighted by their label visibility, BCE for the visibility.
"""
import torch
import torch.nn.functional as F

from detector_model import STRIDES, anchor_centres

LEVEL_RANGES = {8: (0.0, 64.0), 16: (32.0, 160.0), 32: (96.0, 1e9)}
WEIGHTS = {"cls": 1.0, "box": 2.5, "l1": 0.25, "kpt": 1.0, "vis": 0.5}


def flatten(raw):
    """Per-level (pos, size, logits) maps -> (B, N, C) tensors in the output's anchor order."""
    def cat(i):
        return torch.cat([r[i].flatten(2) for r in raw], 2).transpose(1, 2)
    return cat(0), cat(1), cat(2)


def decode_boxes(pos, size, centres, strides):
    """x0 y0 x1 y1 in input pixels from raw (B, N, 2+) offsets and (B, N, 2) log sizes."""
    s = strides[None, :, None]
    xy = pos[..., :2] * s + centres[None]
    wh = torch.exp(size.clamp(max=6.0)) * s
    return torch.cat([xy - wh / 2, xy + wh / 2], -1)


def giou(a, b):
    lt, rb = torch.max(a[:, :2], b[:, :2]), torch.min(a[:, 2:], b[:, 2:])
    inter = (rb - lt).clamp(min=0).prod(1)
    area_a, area_b = (a[:, 2:] - a[:, :2]).prod(1), (b[:, 2:] - b[:, :2]).prod(1)
    union = area_a + area_b - inter + 1e-7
    iou = inter / union
    hull = (torch.max(a[:, 2:], b[:, 2:]) - torch.min(a[:, :2], b[:, :2])).prod(1) + 1e-7
    return iou - (hull - union) / hull, iou


def assign(boxes, centres, strides):
    """Index of the assigned object per anchor (N,), -1 for background."""
    n = centres.shape[0]
    if boxes.shape[0] == 0:
        return torch.full((n,), -1, dtype=torch.long)
    c = (boxes[:, :2] + boxes[:, 2:]) / 2  # (G, 2)
    wh = boxes[:, 2:] - boxes[:, :2]
    longest = wh.max(1).values
    level_ok = torch.zeros(boxes.shape[0], n, dtype=torch.bool)
    for s in STRIDES:
        lo, hi = LEVEL_RANGES[s]
        level_ok |= ((longest >= lo) & (longest < hi))[:, None] & (strides == s)[None]
    inside = ((centres[None] > boxes[:, None, :2]) & (centres[None] < boxes[:, None, 2:])).all(2)
    near = ((centres[None] - c[:, None]).abs() < 1.5 * strides[None, :, None]).all(2)
    d = ((centres[None] - c[:, None]) / strides[None, :, None]).abs().max(2).values  # (G, N)
    cand = level_ok & inside & near
    # Nearest anchor of each allowed level, always.
    for s in STRIDES:
        lv = strides == s
        dd = torch.where(level_ok & lv[None], d, torch.full_like(d, 1e9))
        j = dd.argmin(1)
        ok = dd.gather(1, j[:, None])[:, 0] < 1e8
        cand[torch.arange(boxes.shape[0])[ok], j[ok]] = True
    area = wh.prod(1)[:, None].expand(-1, n)
    area = torch.where(cand, area, torch.full_like(area, float("inf")))
    best = area.min(0)
    return torch.where(torch.isfinite(best.values), best.indices, torch.full_like(best.indices, -1))


class DetectorLoss:
    def __init__(self, nc, nk, size):
        self.nc, self.nk = nc, nk
        self.centres, self.strides = anchor_centres(size)

    def __call__(self, raw, targets):
        pos, size, logits = flatten(raw)
        B, N, _ = pos.shape
        nc, nk = self.nc, self.nk
        cls_t = torch.zeros(B, N, nc)
        idx_b, idx_a, t_box, t_kp, t_cls = [], [], [], [], []
        for b, (cls, boxes, kp) in enumerate(targets):
            g = assign(boxes, self.centres, self.strides)
            a = torch.nonzero(g >= 0)[:, 0]
            if a.numel() == 0:
                continue
            gi = g[a]
            cls_t[b, a, cls[gi]] = 1.0
            idx_b.append(torch.full_like(a, b)), idx_a.append(a)
            t_box.append(boxes[gi]), t_kp.append(kp[gi]), t_cls.append(cls[gi])
        num_pos = max(sum(len(a) for a in idx_a), 1)
        loss = {"cls": F.binary_cross_entropy_with_logits(logits[..., :nc], cls_t, reduction="sum") / num_pos}
        if not idx_a:
            zero = logits.sum() * 0.0
            loss.update(box=zero, l1=zero, kpt=zero, vis=zero)
        else:
            ib, ia = torch.cat(idx_b), torch.cat(idx_a)
            tb, tk = torch.cat(t_box), torch.cat(t_kp)
            c, s = self.centres[ia], self.strides[ia][:, None]
            p_pos, p_size, p_log = pos[ib, ia], size[ib, ia], logits[ib, ia]
            pb = decode_boxes(p_pos[None], p_size[None], c, self.strides[ia])[0]
            g_, _ = giou(pb, tb)
            loss["box"] = (1.0 - g_).sum() / num_pos
            t_xy = ((tb[:, :2] + tb[:, 2:]) / 2 - c) / s
            t_wh = torch.log(((tb[:, 2:] - tb[:, :2]) / s).clamp(min=1e-3))
            loss["l1"] = (F.l1_loss(p_pos[:, :2], t_xy, reduction="sum") + F.l1_loss(p_size, t_wh, reduction="sum")) / num_pos
            vis = tk[..., 2]  # (P, K)
            t_k = (tk[..., :2] - c[:, None]) / s[:, None]
            p_k = p_pos[:, 2:].reshape(-1, nk, 2)
            kerr = (p_k - t_k).abs().sum(2) * vis
            loss["kpt"] = kerr.sum() / vis.sum().clamp(min=1.0)
            loss["vis"] = F.binary_cross_entropy_with_logits(p_log[:, nc:], vis, reduction="sum") / (num_pos * nk)
        loss["total"] = sum(WEIGHTS[k] * loss[k] for k in WEIGHTS)
        return loss
