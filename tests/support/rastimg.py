"""Image helpers for the python tests (standard library only): a minimal PNG
reader (8-bit grey/palette/RGB/RGBA, non-interlaced),
readers for glref-ids and PFM files, and the sRGB encoding."""
import struct
import zlib


def read_png_rgba(path):
    """(width, height, RGBA bytes, top row first) of an 8-bit non-interlaced PNG."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat = 8, bytearray()
    w = h = ch = None
    plte = None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or interlace:
                raise ValueError(f"{path}: only 8-bit non-interlaced PNGs are supported")
            ch = {0: 1, 2: 3, 3: 1, 4: 2, 6: 4}[ctype]
            palette = ctype == 3
            grey = ctype in (0, 4)
        elif kind == b"PLTE":
            plte = body
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + n
    raw = zlib.decompress(bytes(idat))
    stride = w * ch
    out = bytearray(h * stride)
    prev = bytearray(stride)
    i = 0
    for y in range(h):
        ft = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        if ft == 1:
            for x in range(ch, stride):
                line[x] = (line[x] + line[x - ch]) & 255
        elif ft == 2:
            for x in range(stride):
                line[x] = (line[x] + prev[x]) & 255
        elif ft == 3:
            for x in range(stride):
                left = line[x - ch] if x >= ch else 0
                line[x] = (line[x] + ((left + prev[x]) >> 1)) & 255
        elif ft == 4:
            for x in range(stride):
                a = line[x - ch] if x >= ch else 0
                b = prev[x]
                c = prev[x - ch] if x >= ch else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        elif ft != 0:
            raise ValueError(f"{path}: bad filter type {ft}")
        out[y * stride:(y + 1) * stride] = line
        prev = line
    if ch == 4:
        return w, h, bytes(out)
    rgba = bytearray(w * h * 4)
    for k in range(w * h):
        if palette:
            r, g, b = plte[3 * out[k]:3 * out[k] + 3]
            a = 255
        elif grey:
            r = g = b = out[k * ch]
            a = out[k * ch + 1] if ch == 2 else 255
        else:
            r, g, b = out[3 * k:3 * k + 3]
            a = 255
        rgba[4 * k:4 * k + 4] = bytes((r, g, b, a))
    return w, h, bytes(rgba)


def read_png(path):
    """Returns (width, height, 4, RGBA bytes) with rows top first."""
    w, h, rgba = read_png_rgba(path)
    return w, h, 4, rgba


def read_ids(path):
    """glref-ids file -> (w, h, tuple of ids, top row first)."""
    with open(path, "rb") as f:
        header = f.readline().split()
        if header[0] != b"glref-ids":
            raise ValueError(f"{path}: not a glref-ids file")
        w, h = int(header[1]), int(header[2])
        return w, h, struct.unpack(f"<{w * h}I", f.read(4 * w * h))


def read_pfm(path):
    """PFM -> (w, h, channels, tuple of floats, bottom row first)."""
    with open(path, "rb") as f:
        magic = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        ch = 3 if magic == b"PF" else 1
        fmt = "<" if scale < 0 else ">"
        return w, h, ch, struct.unpack(f"{fmt}{w * h * ch}f", f.read(4 * w * h * ch))


def srgb(v):
    """Linear v, clamped to [0, 1], sRGB-encoded and times 255, not rounded:
    the byte an 8-bit PNG holds for it, to within the encoder's rounding."""
    v = min(max(v, 0.0), 1.0)
    return 255.0 * (12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055)
