#!/usr/bin/env python3
"""Writes assets/spoon.obj, the metal spoon of configs/scenes/spoon_forest.yaml (Wand & Strasser 2003,
Figs. 6b and 6c). No spoon mesh ships in a Debian package, so it is built here from two closed parts:

- the bowl, a shell of sheet metal: the inside (concave, the caustic's mirror) is the lower half of the
  ellipsoid with semi-axes A (length, x), DEPTH (y) and B (width, z) centred at (0, DEPTH, 0), so its
  lowest point is the origin; the outside is the lower half of the ellipsoid with every semi-axis
  THICKNESS larger about the same centre; a flat annulus at y = DEPTH closes the rim.
- the handle, a bar of THICKNESS whose centre line leaves the back of the rim (x = -A) along -x and
  rises along a quarter sine by HANDLE_RISE over HANDLE_LENGTH; its width widens from NECK_WIDTH to
  END_WIDTH and closes in a semicircle at the end (width 0, so the bar needs no end cap).

Every vertex carries the exact normal of its surface (the ellipsoid's gradient; for the handle the
cross product of the parametric surface's derivatives, by central differences), pointing out of the
metal, so that the mesh loader's smooth normals are the true ones up to interpolation. Vertices shared
by two faces with different normals (the rim's edges, the handle's corners) are written once per face.
Units are the scene's (the ring of ring_forest.yaml has radius 1). Run: python3 scripts/make_spoon_mesh.py
"""
import math
import os

A, B, DEPTH = 0.45, 0.32, 0.13  # bowl: half length, half width, depth of the inside
THICKNESS = 0.02  # sheet metal
HANDLE_LENGTH, HANDLE_RISE = 1.3, 0.12
NECK_WIDTH, END_WIDTH = 0.08, 0.2
RINGS, AROUND, STATIONS = 12, 40, 24  # bowl: rings from the bottom to the rim, points around; handle: stations
COLUMNS = 4  # handle: points across each face, less one


def normalize(v):
    length = math.sqrt(sum(c * c for c in v))
    return tuple(c / length for c in v)


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


class Mesh:
    def __init__(self):
        self.vertices, self.normals, self.faces = [], [], []

    def vertex(self, position, normal):
        self.vertices.append(position)
        self.normals.append(normalize(normal))
        return len(self.vertices)  # OBJ indices start at 1

    def quad(self, a, b, c, d):
        self.faces.append((a, b, c))
        self.faces.append((a, c, d))


def bowl_surface(mesh, extra, inward):
    """Lower half of the ellipsoid with semi-axes (A, DEPTH, B) + extra; normals into the bowl if inward."""
    ax, ay, az = A + extra, DEPTH + extra, B + extra
    sign = -1.0 if inward else 1.0

    def point(theta, phi):
        p = (ax * math.sin(theta) * math.cos(phi), DEPTH - ay * math.cos(theta), az * math.sin(theta) * math.sin(phi))
        gradient = (p[0] / ax**2, (p[1] - DEPTH) / ay**2, p[2] / az**2)
        return mesh.vertex(p, tuple(sign * g for g in gradient))

    pole = point(0.0, 0.0)
    rings = []
    for i in range(1, RINGS + 1):
        theta = 0.5 * math.pi * i / RINGS
        rings.append([point(theta, 2.0 * math.pi * j / AROUND) for j in range(AROUND)])
    for j in range(AROUND):
        mesh.faces.append((pole, rings[0][j], rings[0][(j + 1) % AROUND]))
    for i in range(RINGS - 1):
        for j in range(AROUND):
            k = (j + 1) % AROUND
            mesh.quad(rings[i][j], rings[i + 1][j], rings[i + 1][k], rings[i][k])


def rim(mesh):
    inner = [mesh.vertex((A * math.cos(phi), DEPTH, B * math.sin(phi)), (0.0, 1.0, 0.0))
             for phi in (2.0 * math.pi * j / AROUND for j in range(AROUND))]
    outer = [mesh.vertex(((A + THICKNESS) * math.cos(phi), DEPTH, (B + THICKNESS) * math.sin(phi)), (0.0, 1.0, 0.0))
             for phi in (2.0 * math.pi * j / AROUND for j in range(AROUND))]
    for j in range(AROUND):
        k = (j + 1) % AROUND
        mesh.quad(inner[j], outer[j], outer[k], inner[k])


def handle_width(s):
    """Width at arc parameter s in [0, 1]: smooth widening, then a semicircular end."""
    t = s * s * (3.0 - 2.0 * s)
    width = NECK_WIDTH + (END_WIDTH - NECK_WIDTH) * t
    end = 0.5 * END_WIDTH / HANDLE_LENGTH  # the semicircle's radius in s
    if s > 1.0 - end:
        width *= math.sqrt(max(0.0, 1.0 - ((s - (1.0 - end)) / end) ** 2))
    return width


def handle_point(s, across, up):
    """Point of the handle's surface: across in [-1, 1] over the width, up in [-1, 1] over the thickness."""
    x = -(A + 0.5 * THICKNESS) - HANDLE_LENGTH * s
    y = DEPTH + HANDLE_RISE * math.sin(0.5 * math.pi * s)
    # The cross-section is perpendicular to the centre line (in the xy-plane).
    tangent = normalize((-HANDLE_LENGTH, HANDLE_RISE * 0.5 * math.pi * math.cos(0.5 * math.pi * s), 0.0))
    normal = (-tangent[1], tangent[0], 0.0)
    if normal[1] < 0.0:
        normal = (-normal[0], -normal[1], 0.0)
    half_up = 0.5 * THICKNESS * up
    return (x + normal[0] * half_up, y + normal[1] * half_up, 0.5 * handle_width(s) * across)


def handle_side(mesh, side):
    """One of the bar's four faces; side: (across, up) of its two edges as functions of v in [0, 1]."""
    columns = COLUMNS
    h = 1e-5

    def vertex(s, v):
        across, up = side(v)
        p = handle_point(s, across, up)
        s0, s1 = max(0.0, s - h), min(1.0, s + h)
        ds = tuple((a - b) / (s1 - s0) for a, b in zip(handle_point(s1, across, up), handle_point(s0, across, up)))
        v0, v1 = max(0.0, v - h), min(1.0, v + h)
        dv = tuple((a - b) / (v1 - v0) for a, b in zip(handle_point(s, *side(v1)), handle_point(s, *side(v0))))
        n = cross(ds, dv)
        if math.sqrt(sum(c * c for c in n)) < 1e-12:  # the closed end: the direction along the bar
            n = (-1.0, 0.0, 0.0)
        return mesh.vertex(p, n)

    grid = [[vertex(i / STATIONS, j / columns) for j in range(columns + 1)] for i in range(STATIONS + 1)]
    for i in range(STATIONS):
        for j in range(columns):
            mesh.quad(grid[i][j], grid[i + 1][j], grid[i + 1][j + 1], grid[i][j + 1])


def outward(mesh, first_vertex, centre_of):
    """Turns the normals written since first_vertex away from the bar's centre line."""
    for index in range(first_vertex, len(mesh.vertices)):
        p, n = mesh.vertices[index], mesh.normals[index]
        c = centre_of(p)
        if sum((a - b) * m for a, b, m in zip(p, c, n)) < 0.0:
            mesh.normals[index] = tuple(-m for m in n)


def handle(mesh):
    first = len(mesh.vertices)
    handle_side(mesh, lambda v: (2.0 * v - 1.0, 1.0))   # top
    handle_side(mesh, lambda v: (2.0 * v - 1.0, -1.0))  # bottom
    handle_side(mesh, lambda v: (1.0, 2.0 * v - 1.0))   # +z side
    handle_side(mesh, lambda v: (-1.0, 2.0 * v - 1.0))  # -z side

    def centre_of(p):
        s = min(1.0, max(0.0, (-(A + 0.5 * THICKNESS) - p[0]) / HANDLE_LENGTH))
        return handle_point(s, 0.0, 0.0)

    outward(mesh, first, centre_of)
    # The neck's start cap sits inside the rim's metal; it closes the bar. A fan from its centre through
    # every point of the four faces' first station, so that each edge meets exactly one other.
    steps = [2.0 * k / COLUMNS - 1.0 for k in range(COLUMNS)]
    outline = ([(a, -1.0) for a in steps] + [(1.0, u) for a, u in zip(steps, steps)] +
               [(-a, 1.0) for a in steps] + [(-1.0, -u) for u in steps])
    centre = mesh.vertex(handle_point(0.0, 0.0, 0.0), (1.0, 0.0, 0.0))
    ring = [mesh.vertex(handle_point(0.0, a, u), (1.0, 0.0, 0.0)) for a, u in outline]
    for k in range(len(ring)):
        mesh.faces.append((centre, ring[k], ring[(k + 1) % len(ring)]))


def main():
    mesh = Mesh()
    bowl_surface(mesh, 0.0, inward=True)
    bowl_surface(mesh, THICKNESS, inward=False)
    rim(mesh)
    handle(mesh)
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "assets", "spoon.obj")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as out:
        out.write("# The spoon of configs/scenes/spoon_forest.yaml, written by scripts/make_spoon_mesh.py (do not edit)\n")
        out.write(f"# bowl {2 * A} x {2 * B} x {DEPTH} (inside), sheet {THICKNESS}; handle {HANDLE_LENGTH} long\n")
        for p in mesh.vertices:  # rounded first, so that a vertex written twice is the same text (no "-0")
            out.write("v {:.5f} {:.5f} {:.5f}\n".format(*(round(c, 5) + 0.0 for c in p)))
        for n in mesh.normals:
            out.write("vn {:.5f} {:.5f} {:.5f}\n".format(*n))
        for f in mesh.faces:
            out.write("f {0}//{0} {1}//{1} {2}//{2}\n".format(*f))
    print(f"{path}: {len(mesh.vertices)} vertices, {len(mesh.faces)} triangles")


if __name__ == "__main__":
    main()
