"""A reader of the OpenEXR files rast writes (scanline, NO or ZIP/ZIPS
compression, HALF/FLOAT/UINT channels), standard library only, so the CLI
tests check the written bytes without OpenEXR's Python bindings (not in
Debian). Follows the OpenEXR file layout document: magic and version, the
header's attributes, the line offset table, then chunks of (y, size, data);
ZIP chunks are zlib streams of the bytes split into even and odd halves and
delta-coded."""
import struct
import zlib

_PIXEL = {0: ("I", 4), 1: ("e", 2), 2: ("f", 4)}  # UINT, HALF, FLOAT
_LINES = {0: 1, 2: 1, 3: 16}  # NO, ZIPS, ZIP compression: scanlines per chunk


def _undo_zip(data, n):
    t = bytearray(zlib.decompress(data))
    assert len(t) == n, (len(t), n)
    for i in range(1, n):
        t[i] = (t[i - 1] + t[i] - 128) & 0xFF
    half = (n + 1) // 2
    out = bytearray(n)
    out[0::2], out[1::2] = t[:half], t[half:]
    return bytes(out)


def read_exr(path):
    """(header dict, {channel: list of rows, top row first}) of an EXR file."""
    d = open(path, "rb").read()
    magic, version = struct.unpack_from("<iI", d, 0)
    if magic != 20000630:
        raise ValueError(f"{path}: not an OpenEXR file")
    if version & 0x200 or version & 0x1000:
        raise ValueError(f"{path}: tiled or multi-part files are not read here")
    off, header = 8, {}
    while d[off] != 0:
        name_end = d.index(b"\0", off)
        name = d[off:name_end].decode()
        type_end = d.index(b"\0", name_end + 1)
        typ = d[name_end + 1:type_end].decode()
        (size,) = struct.unpack_from("<i", d, type_end + 1)
        header[name] = (typ, d[type_end + 5:type_end + 5 + size])
        off = type_end + 5 + size
    off += 1
    channels, raw = [], header["channels"][1]
    p = 0
    while raw[p] != 0:
        e = raw.index(b"\0", p)
        (ptype,) = struct.unpack_from("<i", raw, e + 1)  # then pLinear, 3 reserved bytes, x and y sampling
        channels.append((raw[p:e].decode(), ptype))
        p = e + 1 + 16
    xmin, ymin, xmax, ymax = struct.unpack("<iiii", header["dataWindow"][1])
    w, h = xmax - xmin + 1, ymax - ymin + 1
    comp = header["compression"][1][0]
    if comp not in _LINES:
        raise ValueError(f"{path}: compression {comp} is not read here")
    lines = _LINES[comp]
    chunks = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{chunks}Q", d, off)
    rows = {c: [] for c, _ in channels}
    for o in offsets:
        y, size = struct.unpack_from("<ii", d, o)
        data = d[o + 8:o + 8 + size]
        n = min(lines, ymax + 1 - y)
        full = n * w * sum(_PIXEL[t][1] for _, t in channels)
        if comp != 0 and size < full:
            data = _undo_zip(data, full)
        q = 0
        for _ in range(n):
            for c, t in channels:
                fmt, b = _PIXEL[t]
                rows[c].append(list(struct.unpack_from(f"<{w}{fmt}", data, q)))
                q += w * b
    return {"width": w, "height": h, "channels": [c for c, _ in channels],
            "types": {c: t for c, t in channels}, "compression": comp}, rows
