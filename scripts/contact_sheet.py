#!/usr/bin/env python3
"""Contact sheet of PNG frames without image libraries (python3 only).

Usage: contact_sheet.py OUT.png COLUMNS TILE IMAGE|- ...
Each image (8-bit RGB/RGBA, non-interlaced, as stb writes them) is scaled to
TILE x TILE pixels (nearest neighbour) and placed in reading order, COLUMNS
per row, with a 2-pixel white gap; "-" (or an unreadable file) is a grey
tile with a red cross, marking a scene whose first frame is missing.
"""
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, w = 8, b"", None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise ValueError("unsupported PNG layout")
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
    raw = zlib.decompress(idat)
    stride = w * bpp
    rows, prev = [], bytearray(stride)
    for y in range(h):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0
            b = prev[x]
            c = prev[x - bpp] if x >= bpp else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    return w, h, bpp, rows


def tile_of(path, t):
    out = [bytearray(t * 3) for _ in range(t)]
    try:
        if path == "-":
            raise ValueError
        w, h, bpp, rows = read_png(path)
        for y in range(t):
            src = rows[y * h // t]
            for x in range(t):
                o = (x * w // t) * bpp
                out[y][3 * x:3 * x + 3] = src[o:o + 3]
    except (OSError, ValueError, zlib.error, struct.error):
        for y in range(t):
            for x in range(t):
                red = abs(x - y) <= 1 or abs(x + y - t) <= 1
                out[y][3 * x:3 * x + 3] = bytes((200, 30, 30) if red else (150, 150, 150))
    return out


def write_png(path, w, h, rows):
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    out, cols, t, images = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]
    gap = 2
    nrows = (len(images) + cols - 1) // cols
    w, h = cols * (t + gap) + gap, nrows * (t + gap) + gap
    canvas = [bytearray(b"\xff" * (3 * w)) for _ in range(h)]
    for i, img in enumerate(images):
        tile = tile_of(img, t)
        x0, y0 = gap + (i % cols) * (t + gap), gap + (i // cols) * (t + gap)
        for y in range(t):
            canvas[y0 + y][3 * x0:3 * (x0 + t)] = tile[y]
    write_png(out, w, h, canvas)


if __name__ == "__main__":
    main()
