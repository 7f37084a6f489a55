#!/usr/bin/env python3
"""Caustic irradiance of configs/scenes/glass_sphere.yaml, averaged over each pixel, by rays (numpy).

An independent check of the reference (methods/reference), sharing no code with it: parallel light
(3 W/m^2, travelling along (0.4226183, -0.9063078, 0)) falls on a glass sphere (index 1.5, radius 0.5,
centre (0, 0.5, 0)) resting on the floor y = 0 (a 12 x 12 quad). Rays start on a jittered grid over
the sphere's cross-section (stratified: one ray per cell) and are split exactly at every interface
(Fresnel reflection and refraction both followed, with their weights; total internal reflection; up
to 16 internal reflections or a weight below 1e-9): no random choice anywhere. A ray that leaves the
sphere downwards lands on the floor; the camera of the scene file then sees that point or not (the
segment to the camera may cross the sphere), and the point's power is credited to the pixel whose
footprint holds it, weighted by the image-plane area per unit floor area there, |n . q| / z^3 for a
perspective camera (q the point from the camera, z its depth along the view axis; divided by a
pixel's area on the image plane at depth 1). The sum over a pixel is the average over the pixel's area
of E_c at the surface the pixel sees, which is the quantity docs/metrics.md defines ("A pixel's E_c").

Usage:
  glass_sphere_pixel_model.py WIDTH HEIGHT RAYS_PER_SIDE OUT.txt [SEED]
Writes HEIGHT lines of WIDTH numbers (W/m^2, top row first; the light is white, so one channel), and
prints the total flux credited to visible pixels (sum of E times pixel area is not that: it is the
flux that reaches the visible floor, in W). Seeded: the same command writes the same numbers.
"""
import math
import sys

import numpy as np

IOR, RADIUS = 1.5, 0.5
CENTRE = np.array([0.0, 0.5, 0.0])
LIGHT = np.array([0.4226183, -0.9063078, 0.0])
IRRADIANCE = 3.0
FLOOR_HALF = 6.0
CAMERA, LOOK_AT, UP, FOV_DEGREES = np.array([2.9, 0.8, 1.0]), np.array([0.1, 0.28, 0.0]), np.array([0.0, 1.0, 0.0]), 32.0
MAX_INTERNAL, MIN_WEIGHT = 16, 1e-9


def normalize(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def fresnel(cos_i, eta):
    """Unpolarised dielectric reflectance (eta = n_t / n_i); 1 under total internal reflection."""
    sin2_t = (1.0 - cos_i * cos_i) / (eta * eta)
    cos_t = np.sqrt(np.clip(1.0 - sin2_t, 0.0, None))
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return np.where(sin2_t >= 1.0, 1.0, 0.5 * (rs * rs + rp * rp))


def reflect(d, n):
    return d - 2.0 * np.sum(d * n, axis=-1, keepdims=True) * n


def refract(d, n, eta):
    cos_i = -np.sum(d * n, axis=-1, keepdims=True)
    k = np.clip(1.0 - (1.0 - cos_i * cos_i) / (eta * eta), 0.0, None)
    return normalize(d / eta + n * (cos_i / eta - np.sqrt(k)))


class Camera:
    def __init__(self, width, height):
        self.width, self.height = width, height
        self.forward = normalize(LOOK_AT - CAMERA)
        self.right = normalize(np.cross(self.forward, UP))
        self.up = np.cross(self.right, self.forward)
        self.half = math.tan(math.radians(FOV_DEGREES) / 2.0)
        self.per_pixel = 2.0 * self.half / height  # a pixel's side on the image plane at depth 1

    def credit(self, image, points, power):
        """Adds power x (pixels of image area per m^2 of floor) to the pixel each visible floor point is in."""
        q = points - CAMERA
        z = q @ self.forward
        sx, sy = (q @ self.right) / z, (q @ self.up) / z
        px = (sx / (self.width / self.height * self.half) + 1.0) * 0.5 * self.width
        py = (1.0 - sy / self.half) * 0.5 * self.height
        inside = (z > 0.0) & (px >= 0) & (px < self.width) & (py >= 0) & (py < self.height)
        # The segment from the camera to the point must miss the sphere (the floor hides nothing above it).
        length = np.linalg.norm(q, axis=1)
        direction = q / length[:, None]
        oc = CAMERA - CENTRE
        b = direction @ oc
        c = oc @ oc - RADIUS * RADIUS
        disc = b * b - c
        t_near = -b - np.sqrt(np.clip(disc, 0.0, None))
        blocked = (disc > 0.0) & (t_near > 0.0) & (t_near < length)
        keep = inside & ~blocked
        jacobian = np.abs(q[:, 1]) / z ** 3 / self.per_pixel ** 2  # |n . q| / z^3 with n = +y, per pixel area
        np.add.at(image, (py[keep].astype(int), px[keep].astype(int)), power[keep] * jacobian[keep])
        return float(power[keep].sum())


def land(origins, directions, power, camera, image):
    """Rays leaving the sphere: those going down meet the floor; returns the flux credited to visible pixels."""
    down = directions[:, 1] < 0.0
    t = -origins[down, 1] / directions[down, 1]
    points = origins[down] + t[:, None] * directions[down]
    on_floor = (np.abs(points[:, 0]) < FLOOR_HALF) & (np.abs(points[:, 2]) < FLOOR_HALF)
    return camera.credit(image, points[on_floor], power[down][on_floor])


def trace(side, rng, camera, image):
    """One chunk of the jittered grid: rows `side` of cells; returns the flux credited."""
    u_axis = normalize(np.cross(LIGHT, np.array([0.0, 0.0, 1.0])))
    v_axis = np.cross(LIGHT, u_axis)
    cell = 2.0 * RADIUS / side
    credited = 0.0
    rows_per_chunk = max(1, 1_000_000 // side)
    for first_row in range(0, side, rows_per_chunk):
        rows = np.arange(first_row, min(side, first_row + rows_per_chunk))
        iu, iv = np.meshgrid(np.arange(side), rows)
        u = (iu.ravel() + rng.random(iu.size)) * cell - RADIUS
        v = (iv.ravel() + rng.random(iv.size)) * cell - RADIUS
        r2 = u * u + v * v
        hit = r2 < RADIUS * RADIUS
        u, v, r2 = u[hit], v[hit], r2[hit]
        # Entry point: on the sphere's lit side, seen along the light's direction.
        points = CENTRE + u[:, None] * u_axis + v[:, None] * v_axis - np.sqrt(RADIUS * RADIUS - r2)[:, None] * LIGHT
        d = np.broadcast_to(LIGHT, points.shape).copy()
        power = np.full(len(points), IRRADIANCE * cell * cell)
        n = (points - CENTRE) / RADIUS
        f = fresnel(-np.sum(d * n, axis=1), IOR)
        credited += land(points, reflect(d, n), power * f, camera, image)
        d, power = refract(d, n, IOR), power * (1.0 - f)
        for _ in range(MAX_INTERNAL + 1):
            # To the far side of the sphere along d (the chord), then split again.
            oc = points - CENTRE
            b = np.sum(oc * d, axis=1)
            points = points + (-b + np.sqrt(np.clip(b * b - np.sum(oc * oc, axis=1) + RADIUS * RADIUS, 0.0, None)))[:, None] * d
            inward = -(points - CENTRE) / RADIUS
            f = fresnel(-np.sum(d * inward, axis=1), 1.0 / IOR)
            credited += land(points, refract(d, inward, 1.0 / IOR), power * (1.0 - f), camera, image)
            d, power = reflect(d, inward), power * f
            alive = power > MIN_WEIGHT * IRRADIANCE * cell * cell
            points, d, power = points[alive], d[alive], power[alive]
            if len(power) == 0:
                break
    return credited


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    width, height, side, out = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    seed = int(sys.argv[5]) if len(sys.argv) > 5 else 1
    camera = Camera(width, height)
    image = np.zeros((height, width))
    credited = trace(side, np.random.default_rng(seed), camera, image)
    np.savetxt(out, image, fmt="%.7g")
    print(f"rays {side}^2 (inside the disk: about {side * side * math.pi / 4:.3g}); flux on visible pixels {credited:.6f} W")


if __name__ == "__main__":
    main()
