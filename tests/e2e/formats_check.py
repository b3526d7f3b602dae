#!/usr/bin/env python3
"""formats_check.py DIR - reads back the files e2e_formats.sh rendered in DIR
with readers written here from the format specifications (PPM P6/P3, BMP,
PFM), plus ImageMagick's decodes (im_*.rgb) and libpng/OpenEXR's (png16.raw,
exr.raw from imgread), and compares every pixel with the 8-bit PNG of the
same render (im_ref.rgb). 8-bit formats must match exactly; float formats are
gamma-2 encoded and quantized as rt-mpi does and must match to within one
level (float rounding near a level boundary), almost everywhere exactly."""
import math
import os
import struct
import sys

D = sys.argv[1]
passed = failed = 0


def check(name, ok, detail=""):
    global passed, failed
    if ok:
        passed += 1
        print(f"PASS: {name}")
    else:
        failed += 1
        print(f"FAIL: {name} {detail}")


def read(name):
    with open(os.path.join(D, name), "rb") as f:
        return f.read()


def first_diff(a, b):
    if len(a) != len(b):
        return f"(length {len(a)} vs {len(b)})"
    i = next((i for i in range(len(a)) if a[i] != b[i]), None)
    return "" if i is None else f"(first difference at sample {i}: {a[i]} vs {b[i]})"


def ppm_tokens(data, count):
    """The first `count` whitespace-separated header tokens and the offset after them."""
    toks, i = [], 0
    while len(toks) < count:
        while data[i : i + 1].isspace():
            i += 1
        j = i
        while not data[j : j + 1].isspace():
            j += 1
        toks.append(data[i:j].decode())
        i = j
    return toks, i + 1  # exactly one whitespace byte before binary data


def parse_p6(data):
    (magic, w, h, maxval), off = ppm_tokens(data, 4)
    assert magic == "P6", magic
    w, h, maxval = int(w), int(h), int(maxval)
    n = w * h * 3
    if maxval < 256:
        px = list(data[off : off + n])
    else:
        px = list(struct.unpack(f">{n}H", data[off : off + 2 * n]))
    assert off + n * (1 if maxval < 256 else 2) == len(data), "trailing bytes"
    return w, h, maxval, px


def parse_p3(data):
    text = data.decode("ascii")
    tok = text.split()
    assert tok[0] == "P3"
    w, h, maxval = int(tok[1]), int(tok[2]), int(tok[3])
    px = [int(t) for t in tok[4:]]
    lines = text.rstrip("\n").split("\n")
    return w, h, maxval, px, lines


def parse_bmp(data):
    magic, size, _r1, _r2, off = struct.unpack_from("<2sIHHI", data, 0)
    hdr, w, h, planes, bpp, comp, img_size = struct.unpack_from("<IiiHHII", data, 14)
    fields = dict(magic=magic, size=size, actual=len(data), off=off, hdr=hdr, w=w, h=h, planes=planes, bpp=bpp,
                  comp=comp, img_size=img_size)
    stride = (w * 3 + 3) // 4 * 4
    px, pad_zero = [], True
    for y in range(h):
        row = data[off + (h - 1 - y) * stride : off + (h - y) * stride]  # stored bottom-up
        pad_zero &= all(b == 0 for b in row[w * 3 :])
        for x in range(w):
            b, g, r = row[3 * x : 3 * x + 3]
            px += [r, g, b]
    return fields, stride, px, pad_zero


def parse_pfm(data):
    (magic, w, h, scale), off = ppm_tokens(data, 4)
    assert magic == "PF", magic
    w, h, scale = int(w), int(h), float(scale)
    fmt = "<" if scale < 0 else ">"
    n = w * h * 3
    assert off + 4 * n == len(data), "size"
    vals = struct.unpack(f"{fmt}{n}f", data[off:])
    rows = [vals[y * w * 3 : (y + 1) * w * 3] for y in range(h)]
    return w, h, scale, [v for row in reversed(rows) for v in row]  # bottom-up -> top-down


def parse_raw(name, kind):
    data = read(name)
    nl = data.index(b"\n")
    w, h = map(int, data[:nl].split())
    n = w * h * 3
    return w, h, list(struct.unpack((">%dH" if kind == "u16" else "<%df") % n, data[nl + 1 :]))


def quantize(v, levels, top):
    """rt-mpi's tone map: sqrt, clamp to [0, top], times levels, truncated."""
    c = math.sqrt(v) if v > 0 else 0.0
    return int(levels * min(max(c, 0.0), top))


def compare_quantized(name, floats, want, levels, top, most_off):
    """A float keeps 24 bits: rounding it moves sqrt(v) by up to ~3e-8, which
    crosses one of 256 levels for ~1e-5 of the samples and one of 65536
    levels for ~0.2 % of them."""
    diffs = [abs(quantize(v, levels, top) - w) for v, w in zip(floats, want)]
    worst, off = max(diffs), sum(d > 0 for d in diffs)
    check(f"{name}: gamma+quantized matches ({off} of {len(diffs)} samples differ, by at most {worst})",
          len(floats) == len(want) and worst <= 1 and off <= most_off * len(diffs))


W, H = map(int, read("size.txt").split())
ref = list(read("im_ref.rgb"))
check("reference PNG decoded by ImageMagick", len(ref) == W * H * 3, f"({len(ref)} bytes)")

w, h, maxval, px = parse_p6(read("p6.ppm"))
check("P6 header", (w, h, maxval) == (W, H, 255), (w, h, maxval))
check("P6 pixels == PNG pixels", px == ref, first_diff(px, ref))
check("P6 decoded by ImageMagick == PNG", list(read("im_p6.rgb")) == ref)

w, h, maxval, px, lines = parse_p3(read("p3.ppm"))
check("P3 header", (w, h, maxval) == (W, H, 255), (w, h, maxval))
check("P3 layout: 3 header lines, then one 'r g b' line per pixel",
      lines[:3] == ["P3", f"{W} {H}", "255"] and len(lines) == 3 + W * H and
      all(len(l.split()) == 3 for l in lines[3:]), lines[:5])
check("P3 pixels == PNG pixels", px == ref, first_diff(px, ref))
check("P3 decoded by ImageMagick == PNG", list(read("im_p3.rgb")) == ref)

w, h, maxval, px16 = parse_p6(read("p6_16.ppm"))
check("16-bit P6 header", (w, h, maxval) == (W, H, 65535), (w, h, maxval))
check("16-bit P6 high bytes == PNG pixels", [v >> 8 for v in px16] == ref)

f, stride, px, pad_zero = parse_bmp(read("out.bmp"))
check("BMP headers (BM, size, offset 54, BITMAPINFOHEADER, 24 bpp, uncompressed, bottom-up)",
      f["magic"] == b"BM" and f["size"] == f["actual"] and f["off"] == 54 and f["hdr"] == 40 and
      (f["w"], f["h"]) == (W, H) and f["planes"] == 1 and f["bpp"] == 24 and f["comp"] == 0 and
      f["img_size"] == stride * H and f["actual"] == 54 + stride * H, f)
check("BMP row padding is zero", pad_zero)
check("BMP pixels == PNG pixels", px == ref, first_diff(px, ref))
check("BMP decoded by ImageMagick == PNG", list(read("im_bmp.rgb")) == ref)

w, h, scale, pfm = parse_pfm(read("out.pfm"))
check("PFM header (PF, size, little-endian scale -1)", (w, h, scale) == (W, H, -1.0), (w, h, scale))
check("PFM holds linear radiance (not gamma-encoded bytes)", max(pfm) > 0 and any(0 < v < 0.2 for v in pfm))
compare_quantized("PFM", pfm, ref, 256, 0.999, 0.001)

w, h, exr = parse_raw("exr.raw", "f32")
check("EXR (OpenEXR decoder) size", (w, h) == (W, H), (w, h))
check("EXR floats == PFM floats, bit for bit", struct.pack(f"{len(exr)}f", *exr) == struct.pack(f"{len(pfm)}f", *pfm))
compare_quantized("EXR", exr, ref, 256, 0.999, 0.001)

w, h, png16 = parse_raw("png16.raw", "u16")
check("16-bit PNG (libpng decoder) size", (w, h) == (W, H), (w, h))
check("16-bit PNG high bytes == 8-bit PNG", [v >> 8 for v in png16] == ref)
check("16-bit PNG == 16-bit P6", png16 == px16)
compare_quantized("16-bit PNG vs PFM", pfm, png16, 65536, 0.99999, 0.01)

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)
