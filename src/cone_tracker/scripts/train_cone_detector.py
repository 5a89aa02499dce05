#!/usr/bin/env python3
"""Trains cone_tracker's small cone detector for photographs and exports it to ONNX.

  /usr/bin/python3 train_cone_detector.py --data /work/shared/data/images/tracon_train \
      --out ../models/cone_detector.onnx [--minutes 30 | --steps N] [--all] [--resume OLD.pt --lr 1e-3]

Data: YOLO-labelled photos (DATA/images/*.jpg, DATA/labels/*.txt, `class cx cy w h` normalised,
one box per cone); the TraCon train split (README, "Learned detector for photos"). Nothing is
downloaded: the network is trained from scratch on CPU (Debian's python3-torch).

Model (CenterNet-style, anchor-free): a plain conv backbone to stride 32, a top-down path back to
stride 8, and a head with 5 channels per stride-8 cell: sigmoid(cone-centre heat), log(w/8),
log(h/8) (box size in input pixels), and the centre's offset within the cell (cells). Input: the
photo letterboxed to SIZE x SIZE (scaled so its long side is SIZE, top-left aligned, padded with
grey 114), RGB, divided by 255. dnn_detector.cpp preprocesses and decodes the same way.

Validation: photos whose name's MD5 is 0 mod 5 (~20 %) are held out; the script reports
precision/recall at IoU >= 0.5 on both splits for a few score thresholds. --all trains on every
photo (same schedule) once the settings have been chosen on the split.
"""
import argparse
import glob
import hashlib
import math
import os
import pickle
import random
import sys
import time

import cv2
import numpy as np
import torch
import torch.nn as nn
import torch.nn.functional as F

SIZE = 320  # inference input (letterbox), pixels
CROP = 160  # training crop, pixels (the network is fully convolutional)
STRIDE = 8
PAD = 114
CACHE_LONG_SIDE = 640


def is_val(name):
    return int(hashlib.md5(os.path.basename(name).encode()).hexdigest(), 16) % 5 == 0


def load_dataset(data_dir, cache):
    if os.path.exists(cache):
        with open(cache, "rb") as f:
            return pickle.load(f)
    items = []
    paths = glob.glob(os.path.join(data_dir, "images", "*.jpg")) + glob.glob(os.path.join(data_dir, "images", "*.png"))
    for path in sorted(paths):
        img = cv2.imread(path, cv2.IMREAD_COLOR)
        if img is None:
            sys.exit(f"cannot read {path}")
        h, w = img.shape[:2]
        lab = os.path.join(data_dir, "labels", os.path.splitext(os.path.basename(path))[0] + ".txt")
        boxes = []  # x0 y0 x1 y1 in original pixels
        if os.path.exists(lab):
            for line in open(lab):
                p = line.split()
                if len(p) < 5:
                    continue
                cx, cy, bw, bh = [float(v) for v in p[1:5]]
                boxes.append([(cx - bw / 2) * w, (cy - bh / 2) * h, (cx + bw / 2) * w, (cy + bh / 2) * h])
        s = min(1.0, CACHE_LONG_SIDE / max(h, w))
        small = cv2.resize(img, (round(w * s), round(h * s)), interpolation=cv2.INTER_AREA) if s < 1 else img
        items.append({"path": path, "img": cv2.imencode(".png", small)[1], "scale": s, "orig_wh": (w, h),
                      "boxes": np.array(boxes, np.float32).reshape(-1, 4) * s})
    with open(cache, "wb") as f:
        pickle.dump(items, f)
    return items


def decode_img(item):
    return cv2.imdecode(item["img"], cv2.IMREAD_COLOR)


# ---------------------------------------------------------------- augmentation

def photometric(img, rng):
    img = img.astype(np.float32)
    if rng.random() < 0.8:  # hue (small: the cone's colour is the cue), saturation, value
        hsv = cv2.cvtColor(img / 255.0, cv2.COLOR_BGR2HSV)
        hsv[..., 0] = (hsv[..., 0] + rng.uniform(-8, 8)) % 360
        hsv[..., 1] *= rng.uniform(0.6, 1.3)
        hsv[..., 2] *= rng.uniform(0.5, 1.4)
        img = cv2.cvtColor(np.clip(hsv, 0, [360, 1, 1]).astype(np.float32), cv2.COLOR_HSV2BGR) * 255.0
    if rng.random() < 0.5:  # contrast and brightness
        img = (img - 128) * rng.uniform(0.6, 1.4) + 128 + rng.uniform(-30, 30)
    if rng.random() < 0.3:  # gamma (night, shade)
        img = 255.0 * (np.clip(img, 0, 255) / 255.0) ** rng.uniform(0.6, 1.6)
    if rng.random() < 0.05:
        g = cv2.cvtColor(np.clip(img, 0, 255).astype(np.uint8), cv2.COLOR_BGR2GRAY)
        img = np.repeat(g[..., None], 3, 2).astype(np.float32)
    if rng.random() < 0.25:
        k = rng.choice([3, 5])
        img = cv2.GaussianBlur(img, (k, k), 0)
    if rng.random() < 0.25:
        img = img + rng.normal(0, rng.uniform(2, 10), img.shape)
    return np.clip(img, 0, 255).astype(np.uint8)


def random_sample(item, rng):
    """A CROP x CROP training crop at a random scale around the inference scale, with its boxes."""
    img = decode_img(item)
    h, w = img.shape[:2]
    s = SIZE / max(h, w) * math.exp(rng.uniform(math.log(0.55), math.log(1.6)))
    img = cv2.resize(img, (max(1, round(w * s)), max(1, round(h * s))),
                     interpolation=cv2.INTER_AREA if s < 1 else cv2.INTER_LINEAR)
    boxes = item["boxes"] * s
    h, w = img.shape[:2]
    # Crop origin: at random, or (half of the time) around a random cone.
    if len(boxes) and rng.random() < 0.5:
        b = boxes[rng.integers(len(boxes))]
        cx, cy = (b[0] + b[2]) / 2, (b[1] + b[3]) / 2
        x0 = int(cx - rng.uniform(0.15, 0.85) * CROP)
        y0 = int(cy - rng.uniform(0.15, 0.85) * CROP)
    else:
        x0 = int(rng.uniform(min(0, w - CROP), max(0, w - CROP) + 1))
        y0 = int(rng.uniform(min(0, h - CROP), max(0, h - CROP) + 1))
    out = np.full((CROP, CROP, 3), PAD, np.uint8)
    sx0, sy0, sx1, sy1 = max(0, x0), max(0, y0), min(w, x0 + CROP), min(h, y0 + CROP)
    if sx1 > sx0 and sy1 > sy0:
        out[sy0 - y0:sy1 - y0, sx0 - x0:sx1 - x0] = img[sy0:sy1, sx0:sx1]
    boxes = boxes - np.array([x0, y0, x0, y0], np.float32)
    if rng.random() < 0.5:
        out = out[:, ::-1].copy()
        boxes = np.stack([CROP - boxes[:, 2], boxes[:, 1], CROP - boxes[:, 0], boxes[:, 3]], 1) if len(boxes) else boxes
    # Keep a box when most of it is in the crop (a cut cone is still a cone, but not a box to learn).
    keep, ignore = [], []
    for b in boxes:
        area = (b[2] - b[0]) * (b[3] - b[1])
        c = np.clip(b, 0, CROP)
        vis = max(0, c[2] - c[0]) * max(0, c[3] - c[1])
        if area > 0 and vis / area > 0.6:
            keep.append(b)
        elif vis > 0:
            ignore.append(c)
    return photometric(out, rng), np.array(keep, np.float32).reshape(-1, 4), np.array(ignore, np.float32).reshape(-1, 4)


def make_targets(boxes, ignore, size):
    """Heat (Gaussian per cone, 0 at the ignored boxes' cells' weight), size and offset targets."""
    g = size // STRIDE
    heat = np.zeros((g, g), np.float32)
    weight = np.ones((g, g), np.float32)
    reg = np.zeros((4, g, g), np.float32)
    mask = np.zeros((g, g), np.float32)
    for b in ignore:
        x0, y0, x1, y1 = [int(v / STRIDE) for v in b]
        weight[max(0, y0):y1 + 1, max(0, x0):x1 + 1] = 0
    ys, xs = np.mgrid[0:g, 0:g].astype(np.float32)
    for b in sorted(boxes, key=lambda b: -(b[2] - b[0]) * (b[3] - b[1])):  # small cones win
        bw, bh = max(b[2] - b[0], 1.0), max(b[3] - b[1], 1.0)
        cx, cy = (b[0] + b[2]) / 2 / STRIDE, (b[1] + b[3]) / 2 / STRIDE
        ix, iy = int(cx), int(cy)
        if not (0 <= ix < g and 0 <= iy < g):
            continue
        sx, sy = max(0.54 * bw / STRIDE / 6 * 2, 0.7), max(0.54 * bh / STRIDE / 6 * 2, 0.7)
        gauss = np.exp(-((xs - ix) ** 2 / (2 * sx * sx) + (ys - iy) ** 2 / (2 * sy * sy)))
        np.maximum(heat, gauss, out=heat)
        heat[iy, ix] = 1.0
        weight[iy, ix] = 1.0
        reg[:, iy, ix] = [math.log(bw / STRIDE), math.log(bh / STRIDE), cx - ix, cy - iy]
        mask[iy, ix] = 1.0
    return heat, weight, reg, mask


# ---------------------------------------------------------------- model

def cbr(i, o, s=1, k=3):
    return nn.Sequential(nn.Conv2d(i, o, k, s, k // 2, bias=False), nn.BatchNorm2d(o), nn.ReLU(inplace=True))


class ConeNet(nn.Module):
    def __init__(self):
        super().__init__()
        self.s8 = nn.Sequential(cbr(3, 16, 2), cbr(16, 24, 2), cbr(24, 40, 2), cbr(40, 40))
        self.s16 = nn.Sequential(cbr(40, 80, 2), cbr(80, 80))
        self.s32 = nn.Sequential(cbr(80, 128, 2), cbr(128, 128), cbr(128, 128))
        self.l16, self.l8 = cbr(80, 64, k=1), cbr(40, 40, k=1)
        self.t32, self.t16 = cbr(128, 64, k=1), cbr(64, 40, k=1)
        self.m16, self.m8 = cbr(64, 64), cbr(40, 40)
        self.head = nn.Sequential(cbr(40, 32), nn.Conv2d(32, 5, 1))
        self.head[-1].bias.data[0] = -4.6  # initial heat ~0.01

    def forward(self, x):
        c8 = self.s8(x)
        c16 = self.s16(c8)
        c32 = self.s32(c16)
        up = lambda t: F.interpolate(t, scale_factor=2.0, mode="nearest")
        p16 = self.m16(self.l16(c16) + up(self.t32(c32)))
        p8 = self.m8(self.l8(c8) + up(self.t16(p16)))
        o = self.head(p8)
        return torch.cat([torch.sigmoid(o[:, :1]), o[:, 1:]], 1)


def focal_loss(pred, heat, weight):
    pred = pred.clamp(1e-4, 1 - 1e-4)
    pos = heat.eq(1).float()
    pos_loss = torch.log(pred) * (1 - pred) ** 2 * pos
    neg_loss = torch.log(1 - pred) * pred ** 2 * (1 - heat) ** 4 * (1 - pos) * weight
    return -(pos_loss.sum() + neg_loss.sum()) / pos.sum().clamp(min=1)


# ---------------------------------------------------------------- inference and scoring

def letterbox(img):
    h, w = img.shape[:2]
    s = SIZE / max(h, w)
    r = cv2.resize(img, (max(1, round(w * s)), max(1, round(h * s))),
                   interpolation=cv2.INTER_AREA if s < 1 else cv2.INTER_LINEAR)
    out = np.full((SIZE, SIZE, 3), PAD, np.uint8)
    out[:r.shape[0], :r.shape[1]] = r
    return out, s


def to_tensor(bgr_batch):
    x = np.stack(bgr_batch)[..., ::-1].astype(np.float32) / 255.0
    return torch.from_numpy(np.ascontiguousarray(x.transpose(0, 3, 1, 2)))


def decode(out, score_min, nms_iou):
    """out: 5 x g x g numpy -> list of (x0, y0, x1, y1, score) in input pixels; as DecodeDnnHeads."""
    heat = out[0]
    pooled = F.max_pool2d(torch.from_numpy(heat)[None, None], 3, 1, 1)[0, 0].numpy()
    ys, xs = np.nonzero((heat >= pooled) & (heat >= score_min))
    dets = []
    for y, x in zip(ys, xs):
        w, h = STRIDE * math.exp(out[1, y, x]), STRIDE * math.exp(out[2, y, x])
        cx, cy = STRIDE * (x + out[3, y, x]), STRIDE * (y + out[4, y, x])
        dets.append((cx - w / 2, cy - h / 2, cx + w / 2, cy + h / 2, float(heat[y, x])))
    return nms(dets, nms_iou)


def nms(dets, nms_iou):
    kept = []
    for d in sorted(dets, key=lambda d: -d[4]):
        if all(iou(d, k) <= nms_iou for k in kept):
            kept.append(d)
    return kept


def detect(out, out_mirror, width, score_min, nms_iou):
    """DnnDetector::Detect: the photo's and its mirror image's views fused (FuseMirroredViews), NMS,
    then the containment merge. width: the photo's width in input pixels (the mirrored part)."""
    a = decode(out, score_min / 2, nms_iou)
    b = [(width - d[2], d[1], width - d[0], d[3], d[4]) for d in decode(out_mirror, score_min / 2, nms_iou)]
    taken, fused = set(), []
    for d in a:
        best, bj = 0.5, -1
        for j, e in enumerate(b):
            if j not in taken and iou(d, e) >= best:
                best, bj = iou(d, e), j
        if bj < 0:
            fused.append(d[:4] + (d[4] / 2,))
        else:
            taken.add(bj)
            fused.append(tuple((np.array(d) + np.array(b[bj])) / 2))
    fused += [e[:4] + (e[4] / 2,) for j, e in enumerate(b) if j not in taken]
    return merge_contained(nms([f for f in fused if f[4] >= score_min], nms_iou))


def merge_contained(dets, contain_frac=0.7, axis_frac=0.1):
    """A box part of a larger box's cone is merged into it (dnn_detector.cpp's MergeContainedBoxes)."""
    area = lambda d: (d[2] - d[0]) * (d[3] - d[1])
    kept = []
    for d in sorted(dets, key=lambda d: -area(d)):
        for j, k in enumerate(kept):
            ix = max(0.0, min(d[2], k[2]) - max(d[0], k[0]))
            iy = max(0.0, min(d[3], k[3]) - max(d[1], k[1]))
            if area(d) > 0 and ix * iy >= contain_frac * area(d) and \
                    abs((d[0] + d[2]) / 2 - (k[0] + k[2]) / 2) <= axis_frac * (k[2] - k[0]):
                kept[j] = k[:4] + (max(k[4], d[4]),)
                break
        else:
            kept.append(d)
    return sorted(kept, key=lambda d: -d[4])


def iou(a, b):
    ix = max(0.0, min(a[2], b[2]) - max(a[0], b[0]))
    iy = max(0.0, min(a[3], b[3]) - max(a[1], b[1]))
    i = ix * iy
    u = (a[2] - a[0]) * (a[3] - a[1]) + (b[2] - b[0]) * (b[3] - b[1]) - i
    return i / u if u > 0 else 0.0


def match(dets, gts):
    """Greedy, in score order, as /work/score_photos.py: (tp, fp, fn)."""
    used, tp = set(), 0
    for d in dets:
        best, bj = 0.0, -1
        for j, g in enumerate(gts):
            if j not in used:
                v = iou(d, g)
                if v > best:
                    best, bj = v, j
        if best >= 0.5:
            tp += 1
            used.add(bj)
    return tp, len(dets) - tp, len(gts) - len(used)


def predict(model, items, batch=8):
    model.eval()
    outs = []
    with torch.no_grad():
        for i in range(0, len(items), batch):
            chunk = items[i:i + batch]
            imgs = [decode_img(it) for it in chunk]
            lbs = [letterbox(img) for img in imgs]
            widths = [round(img.shape[1] * lb[1]) for img, lb in zip(imgs, lbs)]
            mirrors = [lb[0].copy() for lb in lbs]
            for m, lb, w in zip(mirrors, lbs, widths):
                m[:, :w] = lb[0][:, :w][:, ::-1]
            o = model(to_tensor([l[0] for l in lbs])).numpy()
            om = model(to_tensor(mirrors)).numpy()
            outs += [(o[k], om[k], widths[k], lbs[k][1]) for k in range(len(chunk))]
    return outs


def evaluate(items, outs, thresholds, nms_iou):
    res = {}
    for t in thresholds:
        tp = fp = fn = 0
        for it, (o, om, w, s) in zip(items, outs):
            dets = [(d[0] / s, d[1] / s, d[2] / s, d[3] / s, d[4]) for d in detect(o, om, w, t, nms_iou)]
            a, b, c = match(dets, list(it["boxes"]))
            tp, fp, fn = tp + a, fp + b, fn + c
        res[t] = (tp / max(1, tp + fp), tp / max(1, tp + fn))
    return res


def fmt(res):
    return "  ".join(f"t{t:.2f} P{p:.3f} R{r:.3f}" for t, (p, r) in res.items())


# ---------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", required=True, help="folder with images/ and labels/ (YOLO)")
    ap.add_argument("--out", required=True, help="ONNX file to write")
    ap.add_argument("--minutes", type=float, default=28.0,
                    help="training time: the learning rate's cosine schedule runs over it")
    ap.add_argument("--steps", type=int, default=0,
                    help="run this many steps instead (reproducible; a timed run prints its count)")
    ap.add_argument("--eval-train", action="store_true", help="score the training photos at the end too")
    ap.add_argument("--all", action="store_true", help="train on every photo (no validation split)")
    ap.add_argument("--cache", default="/tmp/cone_detector_cache.pkl", help="decoded, downsized photos")
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--threads", type=int, default=1,
                    help="torch and OpenCV threads (the machine is shared: 1 by default)")
    ap.add_argument("--resume", default="", help="start from these weights (a .pt this script wrote)")
    ap.add_argument("--eval-only", action="store_true",
                    help="only score the --resume weights on the validation photos (with --all: the training ones)")
    ap.add_argument("--lr", type=float, default=3e-3, help="peak learning rate of the warm-up + cosine schedule")
    args = ap.parse_args()

    torch.set_num_threads(args.threads)
    cv2.setNumThreads(args.threads)
    torch.manual_seed(args.seed)
    rng = np.random.default_rng(args.seed)
    items = load_dataset(args.data, args.cache)
    train = [it for it in items if args.all or not is_val(it["path"])]
    val = [it for it in items if not is_val(it["path"])] if args.all else [it for it in items if is_val(it["path"])]
    pos = [it for it in train if len(it["boxes"])]
    print(f"{len(items)} photos: train {len(train)} ({len(pos)} with cones), "
          f"{'no held-out split' if args.all else f'validation {len(val)}'}", flush=True)

    model = ConeNet()
    if args.resume:
        model.load_state_dict(torch.load(args.resume, map_location="cpu"))
        print(f"resumed from {args.resume}", flush=True)
    print(f"parameters: {sum(p.numel() for p in model.parameters())}", flush=True)
    if args.eval_only:
        print(f"  {'train' if args.all else 'val'}  "
              f"{fmt(evaluate(val, predict(model, val), [0.2, 0.25, 0.3, 0.35, 0.4, 0.5], 0.5))}", flush=True)
        return
    per_epoch, batch, max_lr = 256, 16, args.lr
    opt = torch.optim.AdamW(model.parameters(), lr=max_lr, weight_decay=5e-4)
    t0 = time.time()
    step, epoch, done = 0, 0, False
    while not done:
        model.train()
        tot = [0.0, 0.0, 0.0]
        for _ in range(per_epoch // batch):
            # Progress through the schedule: by steps when given, else by the time budget.
            frac = step / args.steps if args.steps else (time.time() - t0) / (60 * args.minutes)
            if frac >= 1:
                done = True
                break
            for g in opt.param_groups:  # 5 % warm-up, then cosine to 0
                g["lr"] = max_lr * (frac / 0.05 if frac < 0.05 else 0.5 * (1 + math.cos(math.pi * (frac - 0.05) / 0.95)))
            imgs, hs, ws, rs, ms = [], [], [], [], []
            for _ in range(batch):
                it = pos[rng.integers(len(pos))] if rng.random() < 0.7 else train[rng.integers(len(train))]
                img, boxes, ign = random_sample(it, rng)
                h, w, r, m = make_targets(boxes, ign, CROP)
                imgs.append(img); hs.append(h); ws.append(w); rs.append(r); ms.append(m)
            out = model(to_tensor(imgs))
            heat, weight = torch.from_numpy(np.stack(hs))[:, None], torch.from_numpy(np.stack(ws))[:, None]
            reg, mask = torch.from_numpy(np.stack(rs)), torch.from_numpy(np.stack(ms))[:, None]
            lh = focal_loss(out[:, :1], heat, weight)
            npos = mask.sum().clamp(min=1)
            lwh = (F.l1_loss(out[:, 1:3], reg[:, :2], reduction="none") * mask).sum() / npos
            loff = (F.l1_loss(out[:, 3:5], reg[:, 2:4], reduction="none") * mask).sum() / npos
            loss = lh + lwh + loff
            opt.zero_grad()
            loss.backward()
            opt.step()
            step += 1
            tot = [tot[0] + lh.item(), tot[1] + lwh.item(), tot[2] + loff.item()]
        epoch += 1
        n = max(1, per_epoch // batch)
        print(f"epoch {epoch} step {step} {(time.time() - t0) / 60:.1f} min  heat {tot[0] / n:.3f} "
              f"size {tot[1] / n:.3f} offset {tot[2] / n:.3f}", flush=True)
        if (epoch % 4 == 0 or done) and not args.all:
            print(f"  val   {fmt(evaluate(val, predict(model, val), [0.2, 0.3, 0.4, 0.5], 0.5))}", flush=True)
        torch.save(model.state_dict(), args.out + ".pt")
    print(f"trained {step} steps of {batch} crops ({CROP} px) in {(time.time() - t0) / 60:.1f} min", flush=True)
    if args.eval_train:
        print(f"  train {fmt(evaluate(train, predict(model, train), [0.2, 0.3, 0.4, 0.5], 0.5))}", flush=True)
    export(model, args.out, val[:4] if val else train[:4])


def export(model, path, check_items):
    model.eval()
    dummy = torch.zeros(1, 3, SIZE, SIZE)
    torch.onnx.export(model, dummy, path, opset_version=11, input_names=["image"], output_names=["heads"],
                      do_constant_folding=True)
    net = cv2.dnn.readNetFromONNX(path)
    worst = 0.0
    for it in check_items:
        lb, _ = letterbox(decode_img(it))
        x = to_tensor([lb])
        with torch.no_grad():
            ref = model(x).numpy()
        net.setInput(x.numpy())
        got = net.forward()
        worst = max(worst, float(np.abs(got - ref).max()))
    print(f"wrote {path} ({os.path.getsize(path) / 1e6:.2f} MB); cv2.dnn vs torch max |diff| {worst:.2e}", flush=True)
    if worst > 1e-3:
        sys.exit("cv2.dnn's output differs from torch's")


if __name__ == "__main__":
    main()
