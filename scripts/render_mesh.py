#!/usr/bin/env python3
"""Renders an ASCII PLY mesh (WriteMesh with binary=false, z up) to a PNG for a quick look, in pure Python:
z-buffered triangles, vertex colors, flat Lambert shading, a gray ground plane at z = 0 (so a model that
floats or sinks shows it), perspective camera orbiting the model.

  scripts/render_mesh.py in.ply out.png [--azimuth 30] [--elevation 20] [--size 480] [--no-ground]
"""
import argparse
import math
import struct
import zlib


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        if "format ascii 1.0" not in header:
            raise SystemExit("render_mesh.py: only ASCII PLY (WriteMesh binary=false)")
        nv = nf = 0
        props = []
        section = None
        for h in header:
            t = h.split()
            if t[:2] == ["element", "vertex"]:
                nv, section = int(t[2]), "v"
            elif t[:2] == ["element", "face"]:
                nf, section = int(t[2]), "f"
            elif t and t[0] == "property" and section == "v":
                props.append(t[-1])
        idx = {p: i for i, p in enumerate(props)}
        verts, cols = [], []
        for _ in range(nv):
            v = f.readline().split()
            verts.append((float(v[idx["x"]]), float(v[idx["y"]]), float(v[idx["z"]])))
            if "red" in idx:
                cols.append(tuple(int(float(v[idx[c]])) for c in ("red", "green", "blue")))
            else:
                cols.append((180, 180, 180))
        faces = []
        for _ in range(nf):
            t = f.readline().split()
            n = int(t[0])
            ids = [int(x) for x in t[1 : n + 1]]
            for k in range(1, n - 1):
                faces.append((ids[0], ids[k], ids[k + 1]))
    return verts, cols, faces


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    l = math.sqrt(dot(a, a)) or 1.0
    return (a[0] / l, a[1] / l, a[2] / l)


def write_png(path, w, h, rgb):
    raw = b"".join(b"\x00" + bytes(rgb[y * w * 3 : (y + 1) * w * 3]) for y in range(h))
    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ply")
    ap.add_argument("png")
    ap.add_argument("--azimuth", type=float, default=30.0)
    ap.add_argument("--elevation", type=float, default=20.0)
    ap.add_argument("--size", type=int, default=480)
    ap.add_argument("--no-ground", action="store_true")
    ap.add_argument("--center", "--centre", dest="center", type=str, default="",
                    help="look at x,y,z (m) instead of the model's center")
    ap.add_argument("--radius", type=float, default=0.0, help="frame this radius (m) around the center")
    a = ap.parse_args()
    verts, cols, faces = read_ply(a.ply)
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    center = [(lo[k] + hi[k]) / 2 for k in range(3)]
    radius = max(1e-9, math.sqrt(sum((hi[k] - lo[k]) ** 2 for k in range(3))) / 2)
    if a.center:
        center = [float(x) for x in a.center.split(",")]
    if a.radius > 0:
        radius = a.radius
    if not a.no_ground:
        g = radius * 1.3
        base = len(verts)
        for dx, dy in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            verts.append((center[0] + dx * g, center[1] + dy * g, 0.0))
            cols.append((200, 200, 190))
        faces += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    az, el = math.radians(a.azimuth), math.radians(a.elevation)
    fwd = norm((-math.cos(el) * math.sin(az), math.cos(el) * math.cos(az), -math.sin(el)))  # looking along
    eye = [center[k] - fwd[k] * radius * 3.2 for k in range(3)]
    right = norm(cross(fwd, (0, 0, 1)))
    up = cross(right, fwd)
    light = norm((0.4, -0.6, 0.8))
    W = H = a.size
    f = W / 2 / math.tan(math.radians(20))
    proj = []
    for v in verts:
        d = sub(v, eye)
        z = dot(d, fwd)
        z = max(z, 1e-6)
        proj.append((W / 2 + f * dot(d, right) / z, H / 2 - f * dot(d, up) / z, z))
    zbuf = [float("inf")] * (W * H)
    img = [235, 240, 248] * (W * H)
    for (i0, i1, i2) in faces:
        p0, p1, p2 = proj[i0], proj[i1], proj[i2]
        n = norm(cross(sub(verts[i1], verts[i0]), sub(verts[i2], verts[i0])))
        shade = 0.35 + 0.65 * abs(dot(n, light))
        c = [min(255, int((cols[i0][k] + cols[i1][k] + cols[i2][k]) / 3 * shade)) for k in range(3)]
        minx, maxx = max(0, int(min(p0[0], p1[0], p2[0]))), min(W - 1, int(max(p0[0], p1[0], p2[0])) + 1)
        miny, maxy = max(0, int(min(p0[1], p1[1], p2[1]))), min(H - 1, int(max(p0[1], p1[1], p2[1])) + 1)
        area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p2[0] - p0[0]) * (p1[1] - p0[1])
        if abs(area) < 1e-12 or minx > maxx or miny > maxy:
            continue
        inv = 1.0 / area
        for y in range(miny, maxy + 1):
            py = y + 0.5
            for x in range(minx, maxx + 1):
                px = x + 0.5
                w0 = ((p1[0] - px) * (p2[1] - py) - (p2[0] - px) * (p1[1] - py)) * inv
                w1 = ((p2[0] - px) * (p0[1] - py) - (p0[0] - px) * (p2[1] - py)) * inv
                w2 = 1.0 - w0 - w1
                if w0 < 0 or w1 < 0 or w2 < 0:
                    continue
                z = w0 * p0[2] + w1 * p1[2] + w2 * p2[2]
                k = y * W + x
                if z < zbuf[k]:
                    zbuf[k] = z
                    img[3 * k : 3 * k + 3] = c
    write_png(a.png, W, H, img)


if __name__ == "__main__":
    main()
