#!/usr/bin/env python3
"""Caustic flux of the glass sphere of configs/scenes/capabilities/glass/ on the visible floor, by rays.

An independent check of the methods, sharing no code with them: rays are traced through a glass sphere
(index 1.5, radius 0.5, centre 2.0 above the floor y = 0) with plain Python, and the caustic flux is
summed over the part of the floor the camera sees (outside the sphere's silhouette from straight above,
inside the 4 x 4 view). Two models:
  two  the physics: Fresnel reflection or refraction chosen at random at every interface, any number of
       internal reflections, the first surface's reflection included; what the reference computes.
  one  pinhole's `interaction: refract` (methods/pinhole/README.md, "Refraction: one interface"): refract
       in with weight 1 - F, then a straight line inside the glass to the floor, never leaving it.
Usage:
  glass_sphere_ray_model.py directional DX DY DZ [RAYS]       light travelling along (DX, DY, DZ), 1 W/m^2
  glass_sphere_ray_model.py point X Y Z RADIUS [RAYS]          point light of 1 W/sr (two only)
  glass_sphere_ray_model.py point_values X Y Z RADIUS [RAYS]   irradiance at the focus's pixel centres
Prints flux in W (per unit irradiance or intensity). Seeded: the same command prints the same numbers.
"""
import math
import random
import sys

IOR, RADIUS, CENTRE = 1.5, 0.5, (0.0, 2.0, 0.0)
VIEW_HALF = 2.0  # the 4 x 4 orthographic view


def add(a, b, s=1.0): return tuple(x + s * y for x, y in zip(a, b))
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def normalize(v): return tuple(x / math.sqrt(dot(v, v)) for x in v)
def reflect(d, n): return add(d, n, -2.0 * dot(d, n))


def fresnel(cos_i, eta):
    """Unpolarised dielectric reflectance; eta = n_transmitted / n_incident; 1 under total reflection."""
    sin2_t = (1.0 - cos_i * cos_i) / (eta * eta)
    if sin2_t >= 1.0: return 1.0
    cos_t = math.sqrt(1.0 - sin2_t)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return 0.5 * (rs * rs + rp * rp)


def refract(d, n, eta):
    cos_i = -dot(d, n)
    k = 1.0 - (1.0 - cos_i * cos_i) / (eta * eta)
    return normalize(add(tuple(x / eta for x in d), n, cos_i / eta - math.sqrt(k)))


def floor_point(origin, d):
    if d[1] >= 0.0: return None
    t = -origin[1] / d[1]
    return (origin[0] + t * d[0], origin[2] + t * d[2])


def visible(p):
    return p is not None and p[0] ** 2 + p[1] ** 2 > RADIUS ** 2 and abs(p[0]) < VIEW_HALF and abs(p[1]) < VIEW_HALF


def basis(axis):
    t = normalize((axis[1], -axis[0], 0.0)) if abs(axis[2]) < 0.9 else (1.0, 0.0, 0.0)
    return t, (axis[1] * t[2] - axis[2] * t[1], axis[2] * t[0] - axis[0] * t[2], axis[0] * t[1] - axis[1] * t[0])


def entry(origin, d):
    oc = add(origin, CENTRE, -1.0)
    b, c = dot(oc, d), dot(oc, oc) - RADIUS ** 2
    if b * b - c < 0.0: return None
    return add(origin, d, -b - math.sqrt(b * b - c))


def physics(hit, d, rnd):
    """Where a ray that hits the sphere at `hit` lands on the floor (None: it does not)."""
    n = normalize(add(hit, CENTRE, -1.0))
    if rnd.random() < fresnel(-dot(d, n), IOR): return floor_point(hit, reflect(d, n))
    d, p = refract(d, n, IOR), hit
    for _ in range(64):
        oc = add(p, CENTRE, -1.0)
        p = add(p, d, -dot(oc, d) + math.sqrt(max(0.0, dot(oc, d) ** 2 - dot(oc, oc) + RADIUS ** 2)))
        inward = tuple(-x for x in normalize(add(p, CENTRE, -1.0)))
        if rnd.random() < fresnel(-dot(d, inward), 1.0 / IOR):
            d = reflect(d, inward)
            continue
        return floor_point(p, refract(d, inward, 1.0 / IOR))
    return None


def directional(direction, rays, rnd):
    d = normalize(direction)
    t, b = basis(d)
    one = two = 0.0
    for _ in range(rays):
        r, a = RADIUS * math.sqrt(rnd.random()), 2.0 * math.pi * rnd.random()
        origin = add(add(add(CENTRE, t, r * math.cos(a)), b, r * math.sin(a)), d, -3.0)
        hit = entry(origin, d)
        if hit is None: continue
        n = normalize(add(hit, CENTRE, -1.0))
        if visible(floor_point(hit, refract(d, n, IOR))): one += 1.0 - fresnel(-dot(d, n), IOR)
        if visible(physics(hit, d, rnd)): two += 1.0
    area = math.pi * RADIUS ** 2
    return one * area / rays, two * area / rays


def point_paths(light, light_radius, rays, rnd):
    """Yields (floor point or None, weight in W per W/sr) for rays from a point light aimed at the sphere."""
    for _ in range(rays):
        z, a = 2.0 * rnd.random() - 1.0, 2.0 * math.pi * rnd.random()
        s = math.sqrt(1.0 - z * z)
        origin = add(light, (s * math.cos(a), z, s * math.sin(a)), light_radius)
        to_centre = add(CENTRE, origin, -1.0)
        axis, distance = normalize(to_centre), math.sqrt(dot(to_centre, to_centre))
        cos_max = math.sqrt(1.0 - (RADIUS / distance) ** 2)
        cz = 1.0 - rnd.random() * (1.0 - cos_max)
        sz, phi = math.sqrt(1.0 - cz * cz), 2.0 * math.pi * rnd.random()
        t, b = basis(axis)
        d = normalize(add(add(tuple(cz * x for x in axis), t, sz * math.cos(phi)), b, sz * math.sin(phi)))
        hit = entry(origin, d)
        yield (physics(hit, d, rnd) if hit else None), 2.0 * math.pi * (1.0 - cos_max)


def main(argv):
    rnd = random.Random(1)
    if argv[1] == "directional":
        rays = int(argv[5]) if len(argv) > 5 else 200000
        one, two = directional(tuple(map(float, argv[2:5])), rays, rnd)
        print(f"visible flux per W/m^2: one interface {one:.4f} W, two interfaces {two:.4f} W, ratio {one / two:.3f}")
    elif argv[1] in ("point", "point_values"):
        light, light_radius = tuple(map(float, argv[2:5])), float(argv[5])
        rays = int(argv[6]) if len(argv) > 6 else 200000
        # The four pixel centres nearest the focus of configs/scenes/capabilities/glass/point_light.yaml.
        points, disc = [(-0.5625, 0.0625), (-0.6875, 0.0625)], 0.015
        flux, near = 0.0, [0.0] * len(points)
        for p, weight in point_paths(light, light_radius, rays, rnd):
            if visible(p): flux += weight
            for i, q in enumerate(points):
                if p is not None and (p[0] - q[0]) ** 2 + (p[1] - q[1]) ** 2 < disc * disc: near[i] += weight
        if argv[1] == "point":
            print(f"visible flux per W/sr: {flux / rays:.4f} W")
        for q, w in zip(points, near):
            if argv[1] == "point_values":
                print(f"irradiance at {q} (disc of {disc}): {w / rays / (math.pi * disc * disc):.3f} W/m^2")
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    if len(sys.argv) < 2: sys.exit(__doc__)
    main(sys.argv)
