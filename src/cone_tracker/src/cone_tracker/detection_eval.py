"""Scores detect_cones' JSON lines against YOLO label files (the core of `evaluate_detections`).

A detection is a cone's bounding box ``[x, y, w, h]`` in pixels with an optional ``score`` (1.0 when
absent); a label is a line ``class cx cy w h`` of ``labels/NAME.txt`` beside ``images/NAME.jpg``, in
fractions of the image's width and height (a missing label file: no cone in the image). Detections
are matched greedily by descending score over all images (as COCO does): each one takes the label of
its image, not yet taken, with the highest IoU, a true positive when that IoU >= the threshold (0.5),
otherwise a false positive; labels left unmatched are missed. The average precision (AP50) is
the area under the all-point interpolated precision-recall curve (VOC 2010+), with one curve point per
distinct score (detections without a score, all 1.0, give a single point: AP = precision x recall).
No ROS: plain Python, numpy only (the figures are drawn by ``detection_plots``).
"""
import dataclasses
import json
import os
from typing import Dict, List, Optional, Tuple

import numpy as np

IOU_THRESHOLD = 0.5


@dataclasses.dataclass
class ImageResult:
    """One image: its labels and detections (pixels, [x, y, w, h]) and what each became."""
    image: str
    labels: np.ndarray                  # (L, 4)
    detections: np.ndarray              # (D, 4)
    scores: np.ndarray                  # (D,)
    size: Optional[Tuple[int, int]]     # (width, height) of the image, None when unknown
    tp: np.ndarray = None               # (D,) bool: detection matched a label
    matched_label: np.ndarray = None    # (D,) index of its label, -1 for a false positive
    best_iou: np.ndarray = None         # (D,) IoU with the label it took (or its best, for a FP)

    @property
    def fp(self):
        return int(np.count_nonzero(~self.tp))

    @property
    def fn(self):
        return len(self.labels) - int(np.count_nonzero(self.tp))

    def missed(self):
        taken = set(int(i) for i in self.matched_label[self.tp])
        return [i for i in range(len(self.labels)) if i not in taken]


@dataclasses.dataclass
class Scores:
    images: List[ImageResult]
    tp: int
    fp: int
    fn: int
    labelled: int
    precision: float
    recall: float
    ap: float
    curve_recall: np.ndarray            # the PR curve, one point per distinct score, descending
    curve_precision: np.ndarray
    iou_threshold: float

    def line(self):
        """The one summary line (precision and recall); ap_line() is the AP's."""
        return ("evaluate_detections: %d images, %d labelled cones, TP %d FP %d FN %d, precision %.3f, "
                "recall %.3f (IoU >= %.2g)" % (len(self.images), self.labelled, self.tp, self.fp, self.fn,
                                               self.precision, self.recall, self.iou_threshold))

    def ap_line(self):
        return "evaluate_detections: AP50 %.3f (all-point interpolation, IoU >= %.2g)" % (self.ap, self.iou_threshold)


class InputError(ValueError):
    """A line, file or field that cannot be read; the message names it."""


def iou(a, b):
    """IoU matrix of boxes a (N, 4) and b (M, 4), [x, y, w, h]; 0 where a box has no area."""
    a = np.asarray(a, dtype=float).reshape(-1, 4)
    b = np.asarray(b, dtype=float).reshape(-1, 4)
    ax1, ay1, ax2, ay2 = a[:, 0:1], a[:, 1:2], a[:, 0:1] + a[:, 2:3], a[:, 1:2] + a[:, 3:4]
    bx1, by1, bx2, by2 = b[:, 0], b[:, 1], b[:, 0] + b[:, 2], b[:, 1] + b[:, 3]
    w = np.clip(np.minimum(ax2, bx2) - np.maximum(ax1, bx1), 0.0, None)
    h = np.clip(np.minimum(ay2, by2) - np.maximum(ay1, by1), 0.0, None)
    inter = w * h
    union = (a[:, 2:3] * a[:, 3:4]) + (b[:, 2] * b[:, 3]) - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1.0), 0.0)


def label_path(image_path, labels_dir=None):
    """labels/NAME.txt for images/NAME.jpg (the last `images` folder of the path); labels_dir overrides."""
    stem = os.path.splitext(os.path.basename(image_path))[0] + ".txt"
    if labels_dir:
        return os.path.join(labels_dir, stem)
    parts = os.path.dirname(image_path).split(os.sep)
    for i in range(len(parts) - 1, -1, -1):
        if parts[i] == "images":
            parts[i] = "labels"
            return os.path.join(os.sep.join(parts), stem)
    return os.path.join(os.path.dirname(image_path), stem)  # no images/ folder: beside the image


def read_labels(path, width, height):
    """YOLO boxes of a label file in pixels (L, 4); an absent file is no cone. Raises InputError naming
    the file and line for a malformed line."""
    if not os.path.exists(path):
        return np.zeros((0, 4))
    boxes = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            fields = line.split()
            if not fields:
                continue
            try:
                if len(fields) != 5:
                    raise ValueError("%d fields, expected 5 (class cx cy w h)" % len(fields))
                cx, cy, w, h = (float(v) for v in fields[1:])
                if not all(np.isfinite([cx, cy, w, h])) or w < 0 or h < 0:
                    raise ValueError("not finite or negative size")
            except ValueError as e:
                raise InputError("%s:%d: bad label line %r (%s)" % (path, n, line.strip(), e))
            boxes.append([(cx - w / 2) * width, (cy - h / 2) * height, w * width, h * height])
    return np.array(boxes, dtype=float).reshape(-1, 4)


def parse_line(line, where):
    """One detect_cones JSON line -> (image path, boxes (D, 4), scores (D,)). Raises InputError naming
    `where` (file:line) for bad JSON, a missing field or an "error" entry."""
    try:
        obj = json.loads(line)
    except json.JSONDecodeError as e:
        raise InputError("%s: not JSON (%s)" % (where, e))
    if not isinstance(obj, dict) or not isinstance(obj.get("image"), str):
        raise InputError("%s: no \"image\" field" % where)
    if "error" in obj:
        raise InputError("%s: detect_cones could not process %s: %s" % (where, obj["image"], obj["error"]))
    cones = obj.get("cones")
    if not isinstance(cones, list):
        raise InputError("%s: %s: no \"cones\" list" % (where, obj["image"]))
    boxes, scores = [], []
    for k, cone in enumerate(cones):
        bbox = cone.get("bbox") if isinstance(cone, dict) else None
        score = cone.get("score", 1.0) if isinstance(cone, dict) else None
        try:
            box = [float(v) for v in bbox]
            score = float(score)
            if len(box) != 4 or not np.all(np.isfinite(box + [score])):
                raise ValueError
        except (TypeError, ValueError):
            raise InputError("%s: %s: cones[%d] has no valid \"bbox\" [x, y, w, h] and \"score\""
                             % (where, obj["image"], k))
        boxes.append(box)
        scores.append(score)
    return obj["image"], np.array(boxes, dtype=float).reshape(-1, 4), np.array(scores, dtype=float)


def image_size(path):
    """(width, height) of an image file, None when it cannot be read."""
    import cv2  # only here: the scoring itself needs numpy only
    if not os.path.isfile(path):
        return None
    im = cv2.imread(path, cv2.IMREAD_UNCHANGED)  # a corrupt file: None (our own line says so)
    return None if im is None else (im.shape[1], im.shape[0])


def load(jsonl_path, labels_dir=None, size_of=image_size, warn=print):
    """ImageResults (unmatched) of a detect_cones JSONL file; a bad line or an unreadable image is
    reported through warn() in one line naming the file and line, and skipped."""
    out = []
    with open(jsonl_path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if not line.strip():
                continue
            where = "%s:%d" % (jsonl_path, n)
            try:
                image, boxes, scores = parse_line(line, where)
                size = size_of(image)
                if size is None:
                    raise InputError("%s: cannot read the image %s (its label's size is unknown)" % (where, image))
                labels = read_labels(label_path(image, labels_dir), *size)
            except (InputError, OSError, UnicodeDecodeError) as e:
                warn("evaluate_detections: %s" % e)
                continue
            out.append(ImageResult(image, labels, boxes, scores, size))
    return out


def average_precision(recall, precision):
    """All-point interpolated AP: the area under the precision envelope (max precision at recall >= r)."""
    r = np.concatenate([[0.0], recall, [1.0]])
    p = np.concatenate([[0.0], precision, [0.0]])
    p = np.maximum.accumulate(p[::-1])[::-1]
    steps = np.nonzero(r[1:] != r[:-1])[0]
    return float(np.sum((r[steps + 1] - r[steps]) * p[steps + 1]))


def score(images: List[ImageResult], iou_threshold=IOU_THRESHOLD) -> Scores:
    """Greedy matching by descending score over all images; fills each ImageResult's tp/matched_label."""
    order = []  # (score, image index, detection index)
    for i, im in enumerate(images):
        im.tp = np.zeros(len(im.detections), dtype=bool)
        im.matched_label = np.full(len(im.detections), -1, dtype=int)
        im.best_iou = np.zeros(len(im.detections))
        order += [(-s, i, d) for d, s in enumerate(im.scores)]
    order.sort(key=lambda x: (x[0], x[1], x[2]))  # stable for equal scores
    taken: Dict[int, np.ndarray] = {i: np.zeros(len(im.labels), dtype=bool) for i, im in enumerate(images)}
    ious = {i: iou(im.detections, im.labels) for i, im in enumerate(images)}
    hits = np.zeros(len(order), dtype=bool)
    for k, (_, i, d) in enumerate(order):
        im = images[i]
        if not len(im.labels):
            continue
        candidates = np.where(taken[i], -1.0, ious[i][d])
        j = int(np.argmax(candidates))
        if candidates[j] >= iou_threshold:
            taken[i][j] = True
            im.tp[d], im.matched_label[d] = True, j
            hits[k] = True
        im.best_iou[d] = candidates[j] if hits[k] else float(ious[i][d].max())
    labelled = sum(len(im.labels) for im in images)
    # One curve point per distinct score (the last detection of each run of equal scores): a threshold
    # cannot split equal scores, so their order (by image) must not shape the curve. Without scores
    # (all 1.0) the curve is one point and AP = precision x recall.
    ends = np.nonzero(np.r_[np.diff([o[0] for o in order]) != 0, True])[0] if order else np.zeros(0, int)
    tp_cum = np.cumsum(hits)[ends]
    fp_cum = np.cumsum(~hits)[ends]
    curve_recall = tp_cum / labelled if labelled else np.zeros(len(ends))
    curve_precision = tp_cum / np.maximum(tp_cum + fp_cum, 1)
    tp, fp = int(hits.sum()), int((~hits).sum())
    return Scores(images=images, tp=tp, fp=fp, fn=labelled - tp, labelled=labelled,
                  precision=tp / (tp + fp) if tp + fp else float("nan"),
                  recall=tp / labelled if labelled else float("nan"),
                  ap=average_precision(curve_recall, curve_precision) if labelled else float("nan"),
                  curve_recall=curve_recall, curve_precision=curve_precision, iou_threshold=iou_threshold)


def errors_json(scores: Scores):
    """Per image with a miss or a false box: the missed labels and the false detections (pixels)."""
    out = []
    for im in scores.images:
        if im.fn == 0 and im.fp == 0:
            continue
        out.append({
            "image": im.image,
            "labels": len(im.labels), "tp": int(im.tp.sum()), "fp": im.fp, "fn": im.fn,
            "missed": [{"bbox": [round(float(v), 2) for v in im.labels[j]]} for j in im.missed()],
            "false": [{"bbox": [round(float(v), 2) for v in im.detections[d]], "score": float(im.scores[d]),
                       "best_iou": round(float(im.best_iou[d]), 3)}
                      for d in range(len(im.detections)) if not im.tp[d]],
        })
    out.sort(key=lambda e: (-(e["fp"] + e["fn"]), e["image"]))
    return {"iou_threshold": scores.iou_threshold, "tp": scores.tp, "fp": scores.fp, "fn": scores.fn,
            "precision": scores.precision, "recall": scores.recall, "ap50": scores.ap, "images": out}


def worst(scores: Scores, n):
    """The n images with the most FN + FP (ties by name), those with at least one error."""
    bad = [im for im in scores.images if im.fn + im.fp > 0]
    return sorted(bad, key=lambda im: (-(im.fn + im.fp), im.image))[:n]
