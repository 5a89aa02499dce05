"""evaluate_detections' figures: the precision-recall curve and a contact sheet of the worst images.

matplotlib's Agg backend (no display); the contact sheet is drawn with OpenCV on the images themselves.
"""
import math

import cv2
import numpy as np

# BGR; labels are drawn first and thick, so a detection on top of its label shows both.
COLOURS = {"label": (255, 160, 0), "tp": (60, 200, 60), "fp": (40, 40, 230), "missed": (255, 0, 255)}
LEGEND = (("label", "label"), ("tp", "true positive"), ("fp", "false positive"), ("missed", "missed label"))


def pr_curve(path, scores):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 5))
    if len(scores.curve_recall):
        r = np.concatenate([[0.0], scores.curve_recall])
        p = np.concatenate([[scores.curve_precision[0]], scores.curve_precision])
        ax.plot(r, p, ".-" if len(r) < 30 else "-", color="#2c7fb8", lw=1.5, label="precision at each score threshold")
        env = np.maximum.accumulate(p[::-1])[::-1]
        ax.step(r, env, where="pre", color="#e6550d", lw=1.0, ls="--", label="all-point interpolation")
    ax.plot([scores.recall], [scores.precision], "o", color="k",
            label="all detections: P %.3f, R %.3f" % (scores.precision, scores.recall))
    ax.set_xlim(0, 1)
    ax.set_ylim(0, 1.02)
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper right", fontsize=8)
    one = " - no scores: one operating point" if len(scores.curve_recall) == 1 else ""
    ax.set_title("detect_cones, IoU >= %.2g: AP50 %.3f (%d images, %d labels)%s"
                 % (scores.iou_threshold, scores.ap, len(scores.images), scores.labelled,
                    "\n" + one.lstrip(" -") if one else ""), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _box(img, box, colour, thickness, scale):
    x, y, w, h = (v * scale for v in box)
    cv2.rectangle(img, (int(round(x)), int(round(y))), (int(round(x + w)), int(round(y + h))), colour, thickness)


def _tile(im, tile_w, tile_h):
    """One image scaled to fit tile_w x tile_h with its boxes and a caption below; None if unreadable."""
    img = cv2.imread(im.image, cv2.IMREAD_COLOR)
    if img is None:
        return None
    scale = min(tile_w / img.shape[1], tile_h / img.shape[0])
    img = cv2.resize(img, (max(1, int(img.shape[1] * scale)), max(1, int(img.shape[0] * scale))),
                     interpolation=cv2.INTER_AREA)
    missed = set(im.missed())
    for j, box in enumerate(im.labels):
        _box(img, box, COLOURS["missed" if j in missed else "label"], 3, scale)
    for d, box in enumerate(im.detections):
        _box(img, box, COLOURS["tp" if im.tp[d] else "fp"], 1, scale)
    tile = np.full((tile_h + 22, tile_w, 3), 255, np.uint8)
    x0 = (tile_w - img.shape[1]) // 2
    tile[:img.shape[0], x0:x0 + img.shape[1]] = img
    caption = "%s labels %d FN %d FP %d" % (im.image.rsplit("/", 1)[-1][:20], len(im.labels), im.fn, im.fp)
    cv2.putText(tile, caption, (3, img.shape[0] + 15), cv2.FONT_HERSHEY_SIMPLEX, 0.4, (0, 0, 0), 1, cv2.LINE_AA)
    return tile


def contact_sheet(path, images, tile_w=300, tile_h=225, columns=4):
    """The given ImageResults in a grid with a legend bar on top; returns how many tiles were drawn."""
    tiles = [t for t in (_tile(im, tile_w, tile_h) for im in images) if t is not None]
    rows = max(1, math.ceil(len(tiles) / columns))
    th, tw = tile_h + 22, tile_w
    sheet = np.full((30 + rows * (th + 4), columns * (tw + 4), 3), 255, np.uint8)
    x = 6
    for key, text in LEGEND:
        cv2.rectangle(sheet, (x, 8), (x + 22, 22), COLOURS[key], 3 if key in ("label", "missed") else 1)
        cv2.putText(sheet, text, (x + 28, 20), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (0, 0, 0), 1, cv2.LINE_AA)
        x += 28 + 9 * len(text) + 16
    if not tiles:
        cv2.putText(sheet, "no image with a missed or false box", (6, 50), cv2.FONT_HERSHEY_SIMPLEX, 0.5,
                    (0, 0, 0), 1, cv2.LINE_AA)
    for k, t in enumerate(tiles):
        r, c = divmod(k, columns)
        sheet[30 + r * (th + 4):30 + r * (th + 4) + th, c * (tw + 4):c * (tw + 4) + tw] = t
    if not cv2.imwrite(path, sheet):
        raise OSError("cannot write %s" % path)
    return len(tiles)
