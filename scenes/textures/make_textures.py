#!/usr/bin/env python3
"""Writes the scenes' texture images (checker.bmp, grid.png, stripes.bmp, marble.png).

Pure Python (no imaging library), so anyone can regenerate them: python3 make_textures.py
"""
import math
import struct
import zlib


def write_bmp(path, w, h, pixel):
    """24-bit BMP, rows stored bottom-up and padded to 4 bytes; pixel(x, y) with y from the top."""
    row_size = (w * 3 + 3) & ~3
    data = bytearray()
    for y in range(h - 1, -1, -1):
        row = bytearray()
        for x in range(w):
            r, g, b = pixel(x, y)
            row += bytes((b, g, r))
        row += b"\0" * (row_size - len(row))
        data += row
    header = struct.pack("<2sIHHI", b"BM", 54 + len(data), 0, 0, 54)
    info = struct.pack("<IiiHHIIiiII", 40, w, h, 1, 24, 0, len(data), 2835, 2835, 0, 0)
    with open(path, "wb") as f:
        f.write(header + info + data)


def write_png(path, w, h, pixel):
    raw = bytearray()
    for y in range(h):
        raw += b"\0"
        for x in range(w):
            raw += bytes(pixel(x, y))

    def chunk(kind, body):
        c = struct.pack(">I", len(body)) + kind + body
        return c + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def checker(x, y):
    # 8x8 squares; the top-left square is light so orientation mistakes show.
    light = ((x // 8) + (y // 8)) % 2 == 0
    return (230, 225, 210) if light else (60, 70, 90)


def grid(x, y):
    # u runs red from left to right, v runs green from bottom (v = 0) to top; black grid lines.
    if x % 16 == 0 or y % 16 == 0:
        return (20, 20, 20)
    return (int(255 * x / 127), int(255 * (127 - y) / 127), 90)


def stripes(x, y):
    t = 0.5 + 0.5 * math.sin(x * 0.35 + 2.0 * math.sin(y * 0.1))
    return (int(120 + 80 * t), int(70 + 50 * t), int(30 + 20 * t))


def marble(x, y):
    t = 0.5 + 0.5 * math.sin((x + 3 * math.sin(y * 0.2) + 2 * math.sin(x * 0.13)) * 0.25)
    v = int(170 + 80 * t)
    return (v, v, min(255, v + 10))


if __name__ == "__main__":
    write_bmp("checker.bmp", 64, 64, checker)
    write_png("grid.png", 128, 128, grid)
    write_bmp("stripes.bmp", 64, 64, stripes)
    write_png("marble.png", 64, 64, marble)
