"""Image helpers for the python tests (standard library only): a minimal PNG
reader (8-bit grey/RGB/RGBA, non-interlaced, as stb and glref write them) and
readers for glref-ids and PFM files."""
import struct
import zlib


def read_png(path):
    """Returns (width, height, channels, bytes) with rows top first."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, w = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or interlace:
                raise ValueError(f"{path}: only 8-bit non-interlaced PNGs")
            ch = {0: 1, 2: 3, 6: 4, 4: 2}[ctype]
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
        pos += 12 + n
    raw = zlib.decompress(idat)
    stride = w * ch
    out = bytearray(h * stride)
    prev = bytearray(stride)
    i = 0
    for y in range(h):
        ft = raw[i]
        line = bytearray(raw[i + 1:i + 1 + stride])
        i += 1 + stride
        for x in range(stride):
            a = line[x - ch] if x >= ch else 0
            b = prev[x]
            c = prev[x - ch] if x >= ch else 0
            if ft == 1:
                line[x] = (line[x] + a) & 255
            elif ft == 2:
                line[x] = (line[x] + b) & 255
            elif ft == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif ft == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        out[y * stride:(y + 1) * stride] = line
        prev = line
    return w, h, ch, bytes(out)


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
