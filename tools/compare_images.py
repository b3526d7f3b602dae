#!/usr/bin/env python3
"""compare_images.py --ref REF.ppm [--block 8] NAME=IMAGE ...

Compares 8-bit images as the viewer sees them (the bytes both programs
write: gamma 2, 0-255) with a reference: per image, each channel's mean, its
difference from the reference's in standard errors (of the mean of the
pixel differences, independent from pixel to pixel for independent renders:
|z| < 3 is within noise), and the RMSE of block means (blocks of --block
pixels square, 0-255) against the reference. An image that agrees with the
reference as well as the reference's program agrees with itself under
another random stream has about the same block RMSE as that run.

Reads PNG (with PIL) and PPM, plain (P3, as the book writes) or binary (P6).
"""
import argparse
import sys

import numpy as np


def read_ppm(path):
    data = open(path, "rb").read()
    tokens, i = [], 0
    # header: magic, width, height, maxval, with comments
    while len(tokens) < 4:
        while i < len(data) and data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            while i < len(data) and data[i:i + 1] != b"\n":
                i += 1
            continue
        j = i
        while j < len(data) and not data[j:j + 1].isspace():
            j += 1
        tokens.append(data[i:j])
        i = j
    magic, w, h, maxval = tokens[0], int(tokens[1]), int(tokens[2]), int(tokens[3])
    if maxval != 255:
        raise ValueError(f"{path}: only 8-bit PPM")
    if magic == b"P3":
        vals = np.array(data[i:].split(), dtype=np.int64)
    elif magic == b"P6":
        vals = np.frombuffer(data[i + 1:], dtype=np.uint8).astype(np.int64)
    else:
        raise ValueError(f"{path}: not a PPM")
    if vals.size < w * h * 3:
        raise ValueError(f"{path}: truncated")
    return vals[: w * h * 3].reshape(h, w, 3).astype(np.float64)


def read_image(path):
    if path.lower().endswith(".ppm"):
        return read_ppm(path)
    from PIL import Image

    img = np.asarray(Image.open(path).convert("RGB"), dtype=np.float64)
    return img


def blocks(img, b):
    h, w = img.shape[0] // b * b, img.shape[1] // b * b
    x = img[:h, :w].reshape(h // b, b, w // b, b, 3)
    return x.mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--ref", required=True)
    ap.add_argument("--block", type=int, default=8)
    ap.add_argument("images", nargs="+", help="NAME=PATH")
    a = ap.parse_args()
    ref = read_image(a.ref)
    rb = blocks(ref, a.block)
    print(f"  display space (8-bit, gamma 2), reference {a.ref}: {ref.shape[1]}x{ref.shape[0]}")
    print("  {:<22} {:>26} {:>26} {:>12}".format("image", "mean R G B", "(mean - ref) / stderr", f"block-{a.block} RMSE"))

    print("  {:<22} {:>26}".format("reference", " ".join(f"{v:7.2f}" for v in ref.reshape(-1, 3).mean(axis=0))))
    status = 0
    for item in a.images:
        name, _, path = item.partition("=")
        img = read_image(path)
        if img.shape != ref.shape:
            print(f"compare_images.py: {path}: {img.shape[1]}x{img.shape[0]}, not the reference's size", file=sys.stderr)
            status = 2
            continue
        # Pixel differences of two independent renders are independent
        # from pixel to pixel: their mean's standard error is their
        # spread over sqrt(pixels).
        d = (img - ref).reshape(-1, 3)
        se = d.std(axis=0, ddof=1) / np.sqrt(d.shape[0])
        z = np.divide(d.mean(axis=0), se, out=np.zeros(3), where=se > 0)
        rmse = float(np.sqrt(((blocks(img, a.block) - rb) ** 2).mean()))
        print("  {:<22} {:>26} {:>26} {:>12.3f}".format(
            name, " ".join(f"{v:7.2f}" for v in img.reshape(-1, 3).mean(axis=0)),
            " ".join(f"{v:+7.2f}" for v in z), rmse))
    return status


if __name__ == "__main__":
    sys.exit(main())
