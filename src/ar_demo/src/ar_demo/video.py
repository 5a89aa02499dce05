"""The overlay video: sensor_msgs/Image frames from a bag to an H.264 MP4 and a contact sheet.

OpenCV's VideoWriter (python3-opencv, FFmpeg backend) writes the MP4. When it cannot (a build
without FFmpeg), the frames go to a PNG sequence instead; the contact sheet is written either way,
so there is always something to look at without a video player.
"""
import os

import cv2
import numpy as np
from cv_bridge import CvBridge, CvBridgeError

# Small bags (256x192) are scaled up so the video is watchable; H.264 needs even sizes.
MIN_VIDEO_WIDTH_PX = 480


_BRIDGE = CvBridge()


def image_to_bgr(msg):
    """sensor_msgs/Image -> HxWx3 uint8 BGR (cv_bridge), or None for an empty frame or an encoding
    cv_bridge cannot turn into bgr8."""
    if msg.height == 0 or msg.width == 0:
        return None
    try:
        return _BRIDGE.imgmsg_to_cv2(msg, desired_encoding="bgr8")
    except CvBridgeError:
        return None


def _scaled(img, scale):
    if scale == 1:
        return img
    return cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST)


def _caption(img, text):
    """Text in a dark band along the bottom, readable on any background."""
    h, w = img.shape[:2]
    band = max(18, h // 16)
    out = img.copy()
    out[h - band :, :] = (out[h - band :, :] * 0.35).astype(np.uint8)
    font_scale = band / 30.0
    cv2.putText(out, text, (6, h - band // 4 - 2), cv2.FONT_HERSHEY_SIMPLEX, font_scale,
                (255, 255, 255), 1, cv2.LINE_AA)
    return out


class VideoResult:
    def __init__(self):
        self.path = None  # the MP4, or the PNG folder when the MP4 could not be written
        self.kind = None  # "mp4" or "png"
        self.frames = 0
        self.fps = 0.0  # the frames' own rate, from their stamps
        self.size = (0, 0)
        self.sheet = None
        self.skipped = 0  # empty frames, or an encoding cv_bridge cannot turn into bgr8


def write_video(frames, out_dir, name="overlay", caption=None, sheet_times=(), fps=30.0):
    """frames: iterable of (t_s, sensor_msgs/Image) in time order. caption(t_s) -> str.

    Writes out_dir/<name>.mp4 (or out_dir/<name>_frames/*.png) at `fps`, each frame held until
    the next one's stamp, so the video plays in real time even when frames were dropped; and
    out_dir/<name>_sheet.png with the first frame at or after each of `sheet_times`.
    """
    result = VideoResult()
    sheet_times = sorted(sheet_times)
    sheet = []
    writer, png_dir, pending = None, None, None
    first_t = last_t = None
    for t_s, msg in frames:
        img = image_to_bgr(msg)
        if img is None:
            result.skipped += 1
            continue
        while len(sheet) < len(sheet_times) and t_s >= sheet_times[len(sheet)] - 1e-6:
            sheet.append((t_s, img))
        scale = max(1, int(np.ceil(MIN_VIDEO_WIDTH_PX / img.shape[1])))
        big = _scaled(img, scale)
        big = big[: big.shape[0] // 2 * 2, : big.shape[1] // 2 * 2]
        if caption is not None:
            big = _caption(big, caption(t_s))
        if writer is None and png_dir is None:
            result.size = (big.shape[1], big.shape[0])
            writer = _open_writer(os.path.join(out_dir, name + ".mp4"), result.size, fps)
            if writer is None:
                png_dir = os.path.join(out_dir, name + "_frames")
                os.makedirs(png_dir, exist_ok=True)
        if writer is not None and pending is not None:
            for _ in range(max(1, int(round((t_s - pending[0]) * fps)))):
                writer.write(pending[1])
        elif png_dir is not None:
            cv2.imwrite(os.path.join(png_dir, "%05d.png" % result.frames), big)
        pending = (t_s, big)
        first_t = t_s if first_t is None else first_t
        last_t = t_s
        result.frames += 1
    if writer is not None:
        writer.write(pending[1])
        writer.release()
        result.path, result.kind = os.path.join(out_dir, name + ".mp4"), "mp4"
    elif png_dir is not None:
        result.path, result.kind = png_dir, "png"
    if result.frames >= 2:
        result.fps = (result.frames - 1) / max(1e-9, last_t - first_t)
    if sheet:
        result.sheet = os.path.join(out_dir, name + "_sheet.png")
        cv2.imwrite(result.sheet, contact_sheet(sheet, caption))
    return result


def _open_writer(path, size, fps=30.0):
    # avc1 (H.264) plays everywhere; mp4v (MPEG-4 part 2) is the fallback some builds only have.
    for fourcc in ("avc1", "mp4v"):
        writer = cv2.VideoWriter(path, cv2.VideoWriter_fourcc(*fourcc), fps, size)
        if writer.isOpened():
            return writer
    return None


def contact_sheet(frames, caption=None, columns=4):
    """frames: [(t_s, BGR image)] of one size -> one image, a grid with a caption per tile."""
    h, w = frames[0][1].shape[:2]
    scale = max(1, int(np.ceil(320 / w)))
    tiles = [_caption(_scaled(img, scale), caption(t) if caption else "t = %.2f s" % t)
             for t, img in frames]
    th, tw = tiles[0].shape[:2]
    rows = (len(tiles) + columns - 1) // columns
    sheet = np.full((rows * (th + 4) + 4, columns * (tw + 4) + 4, 3), 40, np.uint8)
    for i, tile in enumerate(tiles):
        r, c = divmod(i, columns)
        sheet[4 + r * (th + 4) : 4 + r * (th + 4) + th, 4 + c * (tw + 4) : 4 + c * (tw + 4) + tw] = tile
    return sheet
