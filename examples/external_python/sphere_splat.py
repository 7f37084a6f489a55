#!/usr/bin/env python3
"""A caustics renderer outside causticbench, run by its `external` method (methods/external/README.md).

It renders the caustics of glass and mirror spheres under directional lights onto flat receivers, in the
way a researcher's first prototype would: photons are shot at each sphere from its light, refracted
through it (both interfaces, with Fresnel transmittance and absorption; light reflected inside is
dropped) or reflected off its outside, carried to the nearest receiver triangle (nothing else occludes
them), and splatted onto the G-buffer points within a radius of where they land (a disc kernel:
E = sum of flux / (pi r^2)). What it does not model it says on stderr (another light kind, a
non-uniformly scaled sphere, an analytic receiver); causticbench measures what that costs.

    sphere_splat.py WORLD GBUFFER OUT [--photons N] [--radius R] [--seed S] [--stats FILE]

WORLD is the frame's world.json, GBUFFER its gbuffer.exr, OUT the EXR of E_c it writes (W/m^2, RGB);
STATS receives its own time and counts. Needs NumPy and OpenImageIO's Python module (Debian:
python3-numpy python3-openimageio).
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np
import OpenImageIO as oiio


def read_exr(path):
    """The image's pixels (height, width, channels) and its channel names."""
    image = oiio.ImageInput.open(path)
    if image is None:
        sys.exit(f"cannot open {path}: {oiio.geterror()}")
    spec = image.spec()
    pixels = image.read_image(oiio.FLOAT)
    image.close()
    return np.asarray(pixels).reshape(spec.height, spec.width, spec.nchannels), list(spec.channelnames)


def write_exr(path, pixels):
    output = oiio.ImageOutput.create(path)
    output.open(path, oiio.ImageSpec(pixels.shape[1], pixels.shape[0], 3, oiio.FLOAT))
    output.write_image(np.ascontiguousarray(pixels, dtype=np.float32))
    output.close()


def read_ply(path):
    """Positions (n, 3) and triangles (m, 3) of a binary little-endian PLY as causticbench writes it."""
    with open(path, "rb") as file:
        header, vertex_properties, faces, vertices = [], [], 0, 0
        while True:
            line = file.readline().decode("ascii").strip()
            header.append(line)
            if line.startswith("element vertex"):
                vertices = int(line.split()[2])
            elif line.startswith("element face"):
                faces = int(line.split()[2])
            elif line.startswith("property float") and faces == 0:
                vertex_properties.append(line.split()[2])
            elif line == "end_header":
                break
        if "format binary_little_endian 1.0" not in header:
            sys.exit(f"{path}: expected a binary little-endian PLY")
        data = np.frombuffer(file.read(4 * len(vertex_properties) * vertices), dtype="<f4")
        positions = data.reshape(vertices, len(vertex_properties))[:, :3].astype(np.float64)
        record = np.dtype([("count", "u1"), ("index", "<i4", (3,))])
        triangles = np.frombuffer(file.read(record.itemsize * faces), dtype=record)["index"]
    return positions, triangles


def normalize(vectors):
    return vectors / np.linalg.norm(vectors, axis=-1, keepdims=True)


def fresnel_dielectric(cos_incident, eta):
    """Unpolarised Fresnel reflectance from a medium into one of relative index eta; 1 where light is
    totally reflected."""
    sin2_transmitted = (1.0 - cos_incident**2) / eta**2
    total = sin2_transmitted >= 1.0
    cos_transmitted = np.sqrt(np.clip(1.0 - sin2_transmitted, 0.0, 1.0))
    parallel = (eta * cos_incident - cos_transmitted) / (eta * cos_incident + cos_transmitted)
    perpendicular = (cos_incident - eta * cos_transmitted) / (cos_incident + eta * cos_transmitted)
    return np.where(total, 1.0, 0.5 * (parallel**2 + perpendicular**2)), cos_transmitted, total


def refract(direction, normal, eta, cos_incident, cos_transmitted):
    """The transmitted direction of `direction` through a surface whose `normal` faces the incident side."""
    return direction / eta + (cos_incident / eta - cos_transmitted)[:, None] * normal


def sphere_exit(origin, direction, center, radius):
    """Where rays starting on the sphere's surface and pointing into it leave it again."""
    t = -2.0 * np.einsum("ij,ij->i", origin - center, direction)
    return origin + t[:, None] * direction, t


def trace_sphere(light, sphere, photons, rng):
    """Photon origins, directions and flux (RGB) leaving one sphere lit by one directional light."""
    travel = -np.asarray(light["direction_to_light"], dtype=np.float64)
    center, radius, material = sphere
    # A disc of the sphere's radius facing the light, its photons stratified in a square grid.
    helper = np.array([1.0, 0.0, 0.0]) if abs(travel[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = normalize(np.cross(travel, helper))
    v = np.cross(travel, u)
    side = int(math.ceil(math.sqrt(photons)))
    cells = (np.arange(side * side)[:, None] // np.array([side, 1]) % side + rng.random((side * side, 2))) / side
    disc = 2.0 * cells - 1.0
    disc = disc[np.einsum("ij,ij->i", disc, disc) < 1.0]
    flux = np.asarray(light["irradiance"]) * (4.0 * radius**2) / (side * side)  # each grid cell's share
    start = center + radius * (disc[:, :1] * u + disc[:, 1:] * v) - 2.0 * radius * travel
    # Entry point: the first intersection with the sphere.
    offset = start - center
    b = offset @ travel
    t = -b - np.sqrt(np.maximum(b * b - (np.einsum("ij,ij->i", offset, offset) - radius**2), 0.0))
    entry = start + t[:, None] * travel
    normal = (entry - center) / radius
    cos_in = -(normal @ travel)
    direction = np.broadcast_to(travel, entry.shape)
    weight = np.ones((len(entry), 3)) * flux
    if material["type"] == "mirror":
        reflected = direction + 2.0 * cos_in[:, None] * normal
        return entry, reflected, weight * np.asarray(material.get("reflectance", [1.0, 1.0, 1.0]))
    ior = material.get("ior", 1.5)
    reflectance, cos_t, _ = fresnel_dielectric(cos_in, ior)
    # What the outside reflects, and what it lets in.
    mirrored = (entry, direction + 2.0 * cos_in[:, None] * normal, weight * reflectance[:, None])
    inside = normalize(refract(direction, normal, ior, cos_in, cos_t))
    weight *= (1.0 - reflectance)[:, None]
    exit_point, length = sphere_exit(entry, inside, center, radius)
    normal_out = -(exit_point - center) / radius  # facing the inside, where the light comes from
    cos_out = -np.einsum("ij,ij->i", normal_out, inside)
    reflectance, cos_t, total = fresnel_dielectric(cos_out, 1.0 / ior)
    outside = normalize(refract(inside, normal_out, 1.0 / ior, cos_out, cos_t))
    weight *= (1.0 - reflectance)[:, None] * np.exp(-np.outer(length, material.get("absorption", [0.0, 0.0, 0.0])))
    keep = ~total  # light reflected inside the sphere is not followed
    return (np.concatenate([exit_point[keep], mirrored[0]]), np.concatenate([outside[keep], mirrored[1]]),
            np.concatenate([weight[keep], mirrored[2]]))


def land(origins, directions, receivers):
    """The nearest receiver triangle each photon reaches: its object index (-1: none) and the point."""
    nearest = np.full(len(origins), np.inf)
    hit_object = np.full(len(origins), -1)
    for index, corners in receivers:
        for a, b, c in corners:  # Moller-Trumbore, every photon against one triangle at a time
            edge1, edge2 = b - a, c - a
            p = np.cross(directions, edge2)
            determinant = p @ edge1
            ok = np.abs(determinant) > 1e-12
            inverse = np.where(ok, 1.0 / np.where(ok, determinant, 1.0), 0.0)
            s = origins - a
            bu = np.einsum("ij,ij->i", s, p) * inverse
            q = np.cross(s, edge1)
            bv = np.einsum("ij,ij->i", directions, q) * inverse
            t = (q @ edge2) * inverse
            hit = ok & (bu >= 0) & (bv >= 0) & (bu + bv <= 1) & (t > 1e-6) & (t < nearest)
            nearest = np.where(hit, t, nearest)
            hit_object = np.where(hit, index, hit_object)
    points = origins + np.where(np.isfinite(nearest), nearest, 0.0)[:, None] * directions
    return hit_object, points


def splat(points, directions, flux, hit_object, gbuffer, names, camera, radius):
    """E_c at the G-buffer points: each photon's flux spread over the points of its object within
    `radius` of where it landed and facing where it came from."""
    height, width = gbuffer.shape[:2]
    position = gbuffer[:, :, [names.index(f"position.{a}") for a in "XYZ"]]
    normal = gbuffer[:, :, [names.index(f"normal.{a}") for a in "XYZ"]]
    objects = gbuffer[:, :, names.index("object")]
    footprint = gbuffer[:, :, names.index("footprint")]
    receiver = gbuffer[:, :, names.index("receiver")] > 0.5
    image = np.zeros((height, width, 3))
    if not receiver.any() or len(points) == 0:
        return image
    # The image position of each landing point, as causticbench's camera makes its rays.
    eye = np.asarray(camera["position"], dtype=np.float64)
    forward = normalize(np.asarray(camera["look_at"]) - eye)
    right = normalize(np.cross(forward, camera["up"]))
    up = np.cross(right, forward)
    half_height = math.tan(math.radians(camera["fov_degrees"]) / 2.0)
    relative = points - eye
    depth = relative @ forward
    column = ((relative @ right) / depth / (half_height * width / height) + 1.0) * 0.5 * width
    row = (1.0 - (relative @ up) / depth / half_height) * 0.5 * height
    reach = int(min(32, math.ceil(radius / np.median(footprint[receiver])) + 1))
    offsets = np.stack(np.meshgrid(np.arange(-reach, reach + 1), np.arange(-reach, reach + 1)), -1).reshape(-1, 2)
    visible = np.flatnonzero((depth > 0) & (hit_object >= 0))
    for chunk in np.array_split(visible, max(1, len(visible) * len(offsets) // 4_000_000 + 1)):
        x = column[chunk, None].astype(int) + offsets[None, :, 0]
        y = row[chunk, None].astype(int) + offsets[None, :, 1]
        inside = (x >= 0) & (x < width) & (y >= 0) & (y < height)
        x, y = np.clip(x, 0, width - 1), np.clip(y, 0, height - 1)
        distance = np.linalg.norm(position[y, x] - points[chunk, None], axis=-1)
        facing = np.einsum("ijk,ik->ij", normal[y, x], directions[chunk]) < 0.0
        keep = inside & facing & receiver[y, x] & (objects[y, x] == hit_object[chunk, None]) & (distance < radius)
        photon = np.broadcast_to(np.arange(len(chunk))[:, None], keep.shape)[keep]
        np.add.at(image, (y[keep], x[keep]), flux[chunk][photon] / (math.pi * radius**2))
    return image


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("world")
    parser.add_argument("gbuffer")
    parser.add_argument("out")
    parser.add_argument("--photons", type=int, default=100000, help="photons per light and sphere")
    parser.add_argument("--radius", default="auto",
                        help="splat radius in scene units; auto: a median pixel footprint at 10^5 photons, shrinking as "
                             "1 / sqrt(photons) (as many photons per disc at any count), within 0.5 to 8 footprints")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--stats", default="")
    arguments = parser.parse_args()
    start = time.perf_counter()
    with open(arguments.world) as file:
        world = json.load(file)
    folder = os.path.dirname(os.path.abspath(arguments.world))
    gbuffer, names = read_exr(arguments.gbuffer)
    footprint = gbuffer[:, :, names.index("footprint")][gbuffer[:, :, names.index("receiver")] > 0.5]
    if arguments.radius == "auto":
        footprints = min(8.0, max(0.5, math.sqrt(1e5 / arguments.photons)))
        radius = footprints * float(np.median(footprint)) if len(footprint) else 1.0
    else:
        radius = float(arguments.radius)

    spheres, receivers = [], []
    for index, entry in enumerate(world["objects"]):
        matrix = np.asarray(entry["object_to_world"], dtype=np.float64)
        if entry["makes_caustics"]:
            scales = np.linalg.norm(matrix[:3, :3], axis=0)
            if entry["shape"]["type"] != "sphere" or entry["material"]["type"] not in ("glass", "mirror"):
                print(f"sphere_splat: object {entry['name']} ({entry['shape']['type']}, {entry['material']['type']}) "
                      "makes caustics this renderer does not model", file=sys.stderr)
            elif np.ptp(scales) > 1e-9 * scales.max():
                print(f"sphere_splat: sphere {entry['name']} is scaled unevenly; not modelled", file=sys.stderr)
            else:
                spheres.append((matrix[:3, 3], entry["shape"]["radius"] * scales[0], entry["material"]))
        if entry["receives_caustics"]:
            if "triangles" not in entry:
                print(f"sphere_splat: receiver {entry['name']} ({entry['shape']['type']}) is no triangle shape; "
                      "it gets no caustic", file=sys.stderr)
                continue
            positions, triangles = read_ply(os.path.join(folder, entry["triangles"]))
            receivers.append((index, positions[triangles]))

    rng = np.random.default_rng(arguments.seed)
    emitted, landed = 0, 0
    image = np.zeros(gbuffer.shape[:2] + (3,))
    for light in world["lights"]:
        if light["type"] != "directional":
            print(f"sphere_splat: a {light['type']} light is not modelled", file=sys.stderr)
            continue
        for sphere in spheres:
            origins, directions, flux = trace_sphere(light, sphere, arguments.photons, rng)
            hit_object, points = land(origins, directions, receivers)
            emitted += arguments.photons
            landed += int((hit_object >= 0).sum())
            image += splat(points, directions, flux, hit_object, gbuffer, names, world["camera"], radius)
    write_exr(arguments.out, image)
    if arguments.stats:
        with open(arguments.stats, "w") as file:
            json.dump({"time_ms": (time.perf_counter() - start) * 1e3,
                       "counters": {"photons_emitted": emitted, "photons_landed": landed}}, file)


if __name__ == "__main__":
    main()
