"""Dataset of render_dataset's output for the keypoint detector: letterbox to the network input
(grey 114 padding, like ultralytics), augmentation, labels in input pixels.

Conventions: images are fed as RGB float 0..1 (scale 1/255, no mean). Label coordinates use the
continuous pixel convention (a pixel's centre at +0.5), so the letterbox maps them linearly.
No horizontal flips: they would swap the cuboid's left and right corners.
"""
import glob
import os

import cv2
import numpy as np
import torch

cv2.setNumThreads(1)
PAD = 114
NK = 9


def letterbox_affine(w, h, size):
    """Scale and offsets of ultralytics' letterbox of a w x h image into size x size."""
    r = min(size / w, size / h)
    nw, nh = round(w * r), round(h * r)
    return r, (size - nw) / 2.0, (size - nh) / 2.0


def read_labels(path, w, h):
    """(classes (n,), boxes (n, 4) x0 y0 x1 y1 px, keypoints (n, K, 3) x y v px) of one label file."""
    rows = np.loadtxt(path, ndmin=2, dtype=np.float32) if os.path.getsize(path) else np.zeros((0, 5 + 3 * NK), np.float32)
    cls = rows[:, 0].astype(np.int64)
    cx, cy, bw, bh = rows[:, 1] * w, rows[:, 2] * h, rows[:, 3] * w, rows[:, 4] * h
    boxes = np.stack([cx - bw / 2, cy - bh / 2, cx + bw / 2, cy + bh / 2], 1)
    kp = rows[:, 5:].reshape(-1, NK, 3).copy()
    kp[..., 0] *= w
    kp[..., 1] *= h
    return cls, boxes, kp


class KeypointDataset(torch.utils.data.Dataset):
    def __init__(self, root, size=320, augment=False, seed=0, canvas=None):
        """Letterboxed to size x size; with augment, a canvas x canvas window (default size) of a
        randomly scaled (0.65-1.5) and shifted letterbox."""
        self.images = sorted(glob.glob(os.path.join(root, "images", "*.png")))
        if not self.images:
            raise FileNotFoundError(f"no images in {root}/images")
        self.root, self.size, self.augment = root, size, augment
        self.canvas = canvas or size
        self.rng = np.random.default_rng(seed)

    def __len__(self):
        return len(self.images)

    def __getitem__(self, i):
        img = cv2.cvtColor(cv2.imread(self.images[i], cv2.IMREAD_COLOR), cv2.COLOR_BGR2RGB)
        h, w = img.shape[:2]
        stem = os.path.splitext(os.path.basename(self.images[i]))[0]
        cls, boxes, kp = read_labels(os.path.join(self.root, "labels", stem + ".txt"), w, h)
        r, dx, dy = letterbox_affine(w, h, self.size)
        out = self.size
        if self.augment:
            out = self.canvas
            s = r * self.rng.uniform(0.65, 1.5)
            dx = self.rng.uniform(min(0.0, out - w * s), max(0.0, out - w * s))
            dy = self.rng.uniform(min(0.0, out - h * s), max(0.0, out - h * s))
            r = s
        # Continuous coordinates map by u' = r u + d; warpAffine works on pixel indices.
        m = np.float32([[r, 0, dx + 0.5 * r - 0.5], [0, r, dy + 0.5 * r - 0.5]])
        img = cv2.warpAffine(img, m, (out, out), flags=cv2.INTER_LINEAR, borderValue=(PAD, PAD, PAD))
        boxes, kp, cls = self.transform_labels(boxes, kp, cls, r, dx, dy, out)
        if self.augment:
            img = self.photometric(img)
        x = torch.from_numpy(np.ascontiguousarray(img.transpose(2, 0, 1)))  # uint8 RGB CHW
        return x, torch.from_numpy(cls), torch.from_numpy(boxes), torch.from_numpy(kp)

    @staticmethod
    def transform_labels(boxes, kp, cls, r, dx, dy, size):
        boxes = boxes * r + np.float32([dx, dy, dx, dy])
        area = (boxes[:, 2] - boxes[:, 0]) * (boxes[:, 3] - boxes[:, 1])
        clipped = np.clip(boxes, 0, size)
        carea = (clipped[:, 2] - clipped[:, 0]) * (clipped[:, 3] - clipped[:, 1])
        keep = (carea > 0.4 * area) & (clipped[:, 2] - clipped[:, 0] > 2) & (clipped[:, 3] - clipped[:, 1] > 2)
        vis = kp[..., 2] > 0
        kp[..., 0] = np.where(vis, kp[..., 0] * r + dx, 0)
        kp[..., 1] = np.where(vis, kp[..., 1] * r + dy, 0)
        inside = vis & (kp[..., 0] >= 0) & (kp[..., 0] < size) & (kp[..., 1] >= 0) & (kp[..., 1] < size)
        kp[..., 2] = inside.astype(np.float32)
        kp[~inside, :2] = 0
        return clipped[keep].astype(np.float32), kp[keep].astype(np.float32), cls[keep]

    def photometric(self, img):
        rng = self.rng
        hsv = cv2.cvtColor(img, cv2.COLOR_RGB2HSV).astype(np.float32)
        hsv[..., 0] = (hsv[..., 0] + rng.uniform(-4, 4)) % 180
        hsv[..., 1] *= rng.uniform(0.6, 1.4)
        hsv[..., 2] = hsv[..., 2] * rng.uniform(0.6, 1.4) + rng.uniform(-20, 20)
        img = cv2.cvtColor(np.clip(hsv, 0, 255).astype(np.uint8), cv2.COLOR_HSV2RGB)
        if rng.random() < 0.3:
            img = cv2.GaussianBlur(img, (0, 0), rng.uniform(0.5, 1.3))
        if rng.random() < 0.6:
            noise = np.empty(img.shape, np.int16)
            cv2.randn(noise, 0, rng.uniform(2, 10))
            img = np.clip(img.astype(np.int16) + noise, 0, 255).astype(np.uint8)
        return img


def collate(batch):
    """Images (B, 3, S, S) uint8 and targets: per image (classes, boxes, keypoints)."""
    return torch.stack([b[0] for b in batch]), [(b[1], b[2], b[3]) for b in batch]
