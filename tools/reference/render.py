#!/usr/bin/env python3
"""Path-traces a frame that `fur export-frame` wrote: the reference fur is measured
against.

Mitsuba 3 renders the exported USD frame with a physically based hair model (the `hair`
BSDF: Chiang et al. 2016, as pbrt-v3/v4 implement it), the body as a Lambertian mesh, the
same camera (vertical field of view, box pixel filter), the same distant light and a
uniform environment (docs/ground-truth.md derives both from fur's lights). Pixels that
see no geometry take fur's background colour. Writes the linear image (`--out`, PFM,
float32 RGB) and, optionally, an 8-bit sRGB PNG encoded as fur encodes its own
(`--png`).

Each hair's colour becomes absorption by Chiang et al.'s mapping with the fibre's
azimuthal roughness, per B-spline segment of the curve (the colour ramp along a hair is
kept); each polyline is handed to Mitsuba as a B-spline with every vertex written three
times, which is exactly the polyline (Mitsuba 3.9's `linearcurve` gives the hair BSDF a
zero tangent).

    tools/reference/.venv/bin/python tools/reference/render.py frame.usda --out ref.pfm
"""

import argparse
import os
import sys
import tempfile
import time

import numpy as np

MAX_USD_BYTES = 8 << 30


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(1)


def read_frame(path):
    """The exported frame as numpy arrays and numbers."""
    from pxr import Usd, UsdGeom

    try:
        size = os.stat(path).st_size
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    if size > MAX_USD_BYTES:
        fail(f"{path}: {size} bytes, over the limit of {MAX_USD_BYTES}")
    stage = Usd.Stage.Open(path)
    if stage is None:
        fail(f"{path}: not a USD file usd-core can open")
    data = stage.GetRootLayer().customLayerData
    if "fur:resolution" not in data:
        fail(f"{path}: not written by `fur export-frame` (no fur:resolution)")
    width, height = (int(v) for v in data["fur:resolution"])
    frame = {
        "width": width,
        "height": height,
        "background": np.array(data["fur:background"], dtype=np.float32),
    }
    cam = stage.GetPrimAtPath("/World/Camera")
    near, far = cam.GetAttribute("clippingRange").Get()
    frame["camera"] = {
        "eye": list(cam.GetAttribute("fur:eye").Get()),
        "target": list(cam.GetAttribute("fur:target").Get()),
        "up": list(cam.GetAttribute("fur:up").Get()),
        "fov_y": float(cam.GetAttribute("fur:fovY").Get()),
        "near": float(near),
        "far": float(far),
    }
    sun = stage.GetPrimAtPath("/World/Sun")
    frame["sun"] = {
        "direction": np.array(sun.GetAttribute("fur:direction").Get(), dtype=np.float64),
        "irradiance": float(sun.GetAttribute("fur:irradiance").Get()),
    }
    env = stage.GetPrimAtPath("/World/Environment")
    frame["environment"] = float(env.GetAttribute("fur:radiance").Get())
    body = stage.GetPrimAtPath("/World/Body")
    frame["body"] = None
    if body.IsValid():
        mesh = UsdGeom.Mesh(body)
        frame["body"] = {
            "points": np.array(mesh.GetPointsAttr().Get(), dtype=np.float32),
            "normals": np.array(mesh.GetNormalsAttr().Get(), dtype=np.float32),
            "indices": np.array(mesh.GetFaceVertexIndicesAttr().Get(), dtype=np.uint32),
            # One colour, or one per triangle (`uniform`: a texture's).
            "albedo": np.array(mesh.GetDisplayColorAttr().Get(), dtype=np.float32).reshape(-1, 3),
        }
    hair = stage.GetPrimAtPath("/World/Hair")
    curves = UsdGeom.BasisCurves(hair)
    counts = np.array(curves.GetCurveVertexCountsAttr().Get(), dtype=np.int64)
    frame["hair"] = {
        "counts": counts,
        "points": np.array(curves.GetPointsAttr().Get(), dtype=np.float32).reshape(-1, 3),
        "widths": np.array(curves.GetWidthsAttr().Get(), dtype=np.float32),
        "colors": np.array(curves.GetDisplayColorAttr().Get(), dtype=np.float32).reshape(-1, 3),
        "fibre": {
            name: float(hair.GetAttribute(f"fur:fibre:{name}").Get())
            for name in (
                "longitudinalRoughness",
                "azimuthalRoughness",
                "cuticleTiltDegrees",
                "ior",
            )
        },
    }
    if len(counts) and (counts.min() < 2 or counts.sum() != len(frame["hair"]["points"])):
        fail(f"{path}: the hair's vertex counts do not match its points")
    return frame


def sigma_a_from_color(color, beta_n):
    """Chiang et al. 2016, section 4.2: the absorption (per unit fibre radius) that gives
    a fibre roughly `color` (linear RGB) after multiple scattering."""
    b = beta_n
    d = 5.969 - 0.215 * b + 2.532 * b**2 - 10.73 * b**3 + 5.574 * b**4 + 0.245 * b**5
    c = np.clip(color, 1e-4, 1.0)
    return (np.log(c) / d) ** 2


def curve_file(hair, directory):
    """The polylines as Mitsuba's B-spline curve file (each vertex three times, radius
    half the width, a blank line after each curve) and, per B-spline segment, the colour
    it takes (the B-spline of the vertex colours at the segment's middle). Vectorised:
    each vertex is formatted once, in one operation, and its line repeated."""
    counts, points, widths, colors = (hair[k] for k in ("counts", "points", "widths", "colors"))
    path = os.path.join(directory, "hair.txt")
    vertices = np.column_stack([points, widths * 0.5])
    text = ("%.9g %.9g %.9g %.9g\n" * len(vertices)) % tuple(vertices.ravel().tolist())
    rows = np.repeat(np.array(text.split("\n")[:-1], dtype=object), 3)
    ends = np.cumsum(3 * counts)
    with open(path, "w") as f:
        for line in np.insert(rows, ends, "").tolist():
            f.write(line)
            f.write("\n")
    # Segment k of a curve of 3n rows blends rows k..k+3; a curve has 3n - 3 of them.
    c = np.repeat(colors, 3, axis=0)
    within = np.arange(len(c)) - np.repeat(ends - 3 * counts, 3 * counts)
    k = np.flatnonzero(within < np.repeat(3 * counts - 3, 3 * counts))
    segment_colors = (c[k] + 23 * c[k + 1] + 23 * c[k + 2] + c[k + 3]) / 48
    return path, segment_colors


def build_scene(frame, args, directory):
    import mitsuba as mi

    cam = frame["camera"]
    scene = {
        "type": "scene",
        "integrator": {
            "type": "path",
            "max_depth": args.max_depth,
            "hide_emitters": True,
        },
        "camera": {
            "type": "perspective",
            "fov": cam["fov_y"],
            "fov_axis": "x" if args.broken == "fov-axis" else "y",
            "near_clip": cam["near"],
            "far_clip": cam["far"],
            "to_world": mi.ScalarTransform4f().look_at(
                origin=cam["eye"], target=cam["target"], up=cam["up"]
            ),
            "film": {
                "type": "hdrfilm",
                "width": frame["width"],
                "height": frame["height"],
                "rfilter": {"type": "box"},
                "pixel_format": "rgba",
            },
            "sampler": {"type": "independent", "sample_count": args.spp},
        },
    }
    sun = frame["sun"]
    # The wrong light unit a renderer may take: radiance-like intensity, no π.
    irradiance_scale = np.pi if args.broken == "light-units" else 1.0
    if sun["irradiance"] > 0:
        scene["sun"] = {
            "type": "directional",
            "direction": (-sun["direction"]).tolist(),
            "irradiance": {"type": "rgb", "value": [sun["irradiance"] / irradiance_scale] * 3},
        }
    if frame["environment"] > 0 and not args.direct_only:
        scene["environment"] = {
            "type": "constant",
            "radiance": {"type": "rgb", "value": [frame["environment"]] * 3},
        }
    body = frame["body"]
    if body is not None and len(body["indices"]):
        mesh = mi.Mesh(
            "body",
            vertex_count=len(body["points"]),
            face_count=len(body["indices"]) // 3,
            has_vertex_normals=True,
        )
        params = mi.traverse(mesh)
        params["vertex_positions"] = body["points"].ravel()
        params["vertex_normals"] = body["normals"].ravel()
        params["faces"] = body["indices"]
        params.update()
        albedo = body["albedo"]
        if len(albedo) == 1:
            reflectance = {"type": "rgb", "value": albedo[0].tolist()}
        elif len(albedo) == len(body["indices"]) // 3:
            mesh.add_attribute("face_albedo", 3, albedo.ravel())
            reflectance = {"type": "mesh_attribute", "name": "face_albedo"}
        else:
            fail(
                f"{args.frame}: the body has {len(albedo)} colours for "
                f"{len(body['indices']) // 3} triangles (expected 1 or one each)"
            )
        mesh.set_bsdf(mi.load_dict({"type": "diffuse", "reflectance": reflectance}))
        scene["body"] = mesh
    hair = frame["hair"]
    if len(hair["counts"]) and not args.no_hair:
        path, segment_colors = curve_file(hair, directory)
        fibre = hair["fibre"]
        sigma_a = sigma_a_from_color(segment_colors, fibre["azimuthalRoughness"])
        texture = mi.Bitmap(sigma_a.reshape(-1, 1, 3).astype(np.float32))
        scene["hair"] = {
            "type": "bsplinecurve",
            "filename": path,
            "bsdf": {
                "type": "hair",
                "longitudinal_roughness": fibre["longitudinalRoughness"],
                "azimuthal_roughness": fibre["azimuthalRoughness"],
                "scale_tilt": fibre["cuticleTiltDegrees"],
                "int_ior": fibre["ior"],
                # One texel per B-spline segment: Mitsuba's curves give v = (segment +
                # t) / segments over the whole shape.
                "sigma_a": {
                    "type": "bitmap",
                    "bitmap": texture,
                    "raw": True,
                    "filter_type": "nearest",
                    "wrap_mode": "clamp",
                },
            },
        }
    return mi.load_dict(scene)


def linear_to_srgb8(x):
    """fur's encoding of linear values as 8-bit sRGB (the sRGB curve, rounded)."""
    x = np.clip(x, 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


def write_pfm(path, rgb):
    """Linear float32 RGB as a little-endian PFM (rows bottom to top)."""
    h, w, _ = rgb.shape
    with open(path + ".partial", "wb") as f:
        f.write(f"PF\n{w} {h}\n-1\n".encode())
        f.write(np.ascontiguousarray(rgb[::-1], dtype="<f4").tobytes())
    os.replace(path + ".partial", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("frame", help="a .usda or .usdc file written by `fur export-frame`")
    parser.add_argument("--out", required=True, help="the linear image (PFM)")
    parser.add_argument("--png", help="also the image as 8-bit sRGB PNG")
    parser.add_argument("--spp", type=int, default=64, help="samples per pixel [64]")
    parser.add_argument("--seed", type=int, default=0, help="the sampler's seed [0]")
    parser.add_argument(
        "--max-depth", type=int, default=64, help="longest path, in bounces [64]"
    )
    parser.add_argument(
        "--also",
        nargs=3,
        action="append",
        default=[],
        metavar=("SEED", "MAX_DEPTH", "OUT"),
        help="another image of the same frame, loaded once: its seed, longest path and "
        "PFM file (repeatable)",
    )
    parser.add_argument(
        "--direct-only", action="store_true", help="no environment light (calibration)"
    )
    parser.add_argument("--no-hair", action="store_true", help="leave the hair out")
    parser.add_argument(
        "--break",
        dest="broken",
        choices=["fov-axis", "mirror", "light-units"],
        help="for tests: a deliberately wrong convention the calibration must catch",
    )
    parser.add_argument(
        "--variant",
        default=os.environ.get("FUR_MITSUBA_VARIANT", "scalar_rgb"),
        help="Mitsuba variant [scalar_rgb; llvm_ad_rgb needs DRJIT_LIBLLVM_PATH]",
    )
    args = parser.parse_args()
    jobs = [(args.seed, args.max_depth, args.out)]
    for seed, depth, out in args.also:
        try:
            jobs.append((int(seed), int(depth), out))
        except ValueError:
            fail(f"--also takes a seed, a longest path and a file, got {seed} {depth} {out}")
    if not (1 <= args.spp <= 1 << 16):
        fail(f"--spp must be 1..65536, got {args.spp}")
    for _, depth, _ in jobs:
        if not (1 <= depth <= 1024):
            fail(f"--max-depth must be 1..1024, got {depth}")
    import mitsuba as mi

    try:
        mi.set_variant(args.variant)
    except Exception as e:  # noqa: BLE001 - Mitsuba raises plain exceptions
        fail(f"Mitsuba variant {args.variant}: {e}")
    start = time.time()
    frame = read_frame(args.frame)
    costs = []
    with tempfile.TemporaryDirectory() as directory:
        scene = build_scene(frame, args, directory)
        loaded = time.time() - start
        for seed, depth, out in jobs:
            begun = time.time()
            integrator = None
            if depth != args.max_depth:
                integrator = mi.load_dict(
                    {"type": "path", "max_depth": depth, "hide_emitters": True}
                )
            image = np.array(mi.render(scene, spp=args.spp, seed=seed, integrator=integrator))
            if args.broken == "mirror":
                image = image[:, ::-1]
            rgb, alpha = image[..., :3], image[..., 3:4]
            rgb = rgb + (1.0 - np.clip(alpha, 0.0, 1.0)) * frame["background"]
            write_pfm(out, rgb.astype(np.float32))
            if args.png and out == args.out:
                mi.Bitmap(linear_to_srgb8(rgb)).write(args.png)
            # What this image alone would have cost: the scene's loading and its samples.
            costs.append(loaded + time.time() - begun)
            print(
                f"wrote {out} ({frame['width']}×{frame['height']}, {args.spp} spp, seed "
                f"{seed}, {len(frame['hair']['counts'])} hairs) in {costs[-1]:.1f} s"
            )
    print("seconds:", " ".join(f"{c:.2f}" for c in costs))

if __name__ == "__main__":
    main()
