#!/usr/bin/env python3
"""Peer reference images for brdfkit, rendered with Mitsuba 3.

(One file past 400 lines on purpose: the conventions it documents, the scene it builds and
the checks of Mitsuba's envmap and of the Blinn-Phong BSDF belong together.)

An independent renderer as a second anchor: a unit sphere under the shipped probes
(assets/probes/{city,studio,sky}.exr, downsampled, see "Probes" below) and under one
directional light, with Mitsuba's own `diffuse` BSDF and with brdfkit's energy-normalised
Blinn-Phong written here as a small Python BSDF. tests/peer.rs renders the same scenes
with brdfkit and compares. CI does not need Mitsuba: the images are stored in
tests/data/peer/ with a JSON file each (Mitsuba version, variant, sample counts, seeds,
measured noise, and every scene parameter the test rebuilds the scene from).

Usage (from the repository root; Mitsuba 3 from PyPI, `pip install mitsuba numpy`):

    python3 scripts/peer/render_peer.py              # all scenes, writes tests/data/peer/
    python3 scripts/peer/render_peer.py --only lambert-city --passes 4 --spp 256

Variant: `llvm_ad_rgb` (the script traces all rays of a pass as one vectorised wavefront,
so the scalar variants are not supported). Dr.Jit's LLVM backend needs libLLVM >= 16; with
an older system LLVM (Debian 12 ships 14 and 15, which fail with "Cannot select: fminimum")
install a newer one and point Dr.Jit at it: `apt-get install libllvm19` and
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1. The stored images took
--passes 64 --spp 4096 (the defaults), about 4 minutes per probe scene on 2 busy cores.

Conventions mapped between the two renderers
============================================

Camera. brdfkit (src/scene/camera.rs): pinhole, look-at (position, target, up), vertical
field of view `fov_y_deg`, right-handed view space looking down -z
(`Mat4::look_to_rh`), image x to the right, y down, one sample per pixel at the pixel
centre (x + 1/2, y + 1/2) (src/raster/setup.rs), no anti-aliasing. Mitsuba: `perspective`
sensor with `to_world = look_at(origin, target, up)`, `fov_axis = 'y'`, same fov, square
film (so fov_x = fov_y in both). Mitsuba's `mi.render` jitters samples over the pixel
(box filter): the image would be the pixel-area average, not the centre value. So this
script does not call `mi.render`: it generates every camera ray itself with
`sensor.sample_ray(position_sample = ((x + 1/2)/W, (y + 1/2)/H))`, i.e. exactly through
the pixel centre, and calls Mitsuba's own `direct` integrator (`integrator.sample`: emitter
sampling + BSDF sampling with MIS) on those rays. Image orientation (row 0 at the top,
+x world to the right for a camera on +z looking at the origin with up +y) is the same in
both; tests/peer.rs checks it with a directional light from +x-ish (a mirrored image would
fail there at once).

Environment orientation. brdfkit (src/conventions.rs, src/env/probe.rs): texel (row, col)
of a W x H probe is centred at u = (col + 1/2)/W, v = (row + 1/2)/H; row 0 is the +y pole;
direction `(-sin(pv) sin(2 pi u), cos(pv), sin(pv) cos(2 pi u))` with pv = pi v: column 0
faces +z, the image centre (u = 1/2) faces -z (what the default camera sees), u = 1/4
faces -x. Right-handed, y up. Mitsuba's `envmap` (src/emitters/envmap.cpp, checked on the
installed 3.9.1 by evaluating a 4x3 map, see `check_envmap_convention`): local direction
`(sin(2 pi u) sin(pi v), cos(pi v), -cos(2 pi u) sin(pi v))`, u = 0 faces -z, u = 1/4 faces
+x. So brdfkit_world = diag(-1, 1, -1) mitsuba_local: a rotation by 180 degrees about +y
(determinant +1, no mirroring). `to_world` is that matrix, written exactly (no sin(pi)
rounding).

Texel grid and interpolation. brdfkit's `full` sampler (the converged reference) puts one
delta light per texel at its centre carrying radiance x exact solid angle: it integrates
the probe as a piecewise-constant function (by the midpoint rule inside each texel).
Mitsuba's envmap is not piecewise constant: it interpolates bilinearly between samples
that sit at u = (col + 1/2)/W horizontally (like brdfkit) but at v = row/(H - 1)
vertically (row 0 exactly on the +y pole, row H-1 on the -y pole; brdfkit's rows are
half a texel in). Handing Mitsuba the probe as is would therefore shift every row by up to
half a texel and blur it. Instead Mitsuba gets the same piecewise-constant function
resampled on a k-times finer grid (`--upsample`, default 8): kW columns at
u = (c + 1/2)/(kW) take the brdfkit texel containing u (a coarse column edge lies exactly
half-way between two fine samples), and kH + 1 rows at v = m/(kH) take the texel
containing v, except rows exactly on a coarse row edge, which take the mean of the two
texels. Bilinear interpolation then equals the step function except on a ramp one fine
texel either side of each edge, antisymmetric about the edge, so its integral against any
smooth weight differs from the step's only at second order in 1/k. What the naive choice
costs (Mitsuba given the probe file directly, k = 1 and its own row convention) is
measured per environment scene and recorded in the JSON (`naive_envmap`).

Negative and non-finite texels. The shipped probes are DWAB-compressed and hold negative
channels (assets/probes/README.md). brdfkit's loader clamps each negative channel to 0
(src/env/probe.rs, `Probe::from_texels`) and refuses NaN/Inf unless told to zero them.
This script does the same per channel (`np.maximum(x, 0)`, and fails on non-finite
texels) before anything else, so Mitsuba sees the radiance brdfkit sees.

Probes. A 512x256 probe is 131072 lights for brdfkit's `full` reference; the test must run
in seconds on 2 cores, so both renderers use a downsampled copy stored here
(`probe-NAME-128x64.exr`): 4x4 blocks averaged with exact solid-angle weights per row
(`(2 pi / W)(cos top - cos bottom)`, as brdfkit's `probe_texel_solid_angle`), which keeps
the probe's total power exactly (up to f32 storage). brdfkit loads that file through its
own loader; Mitsuba gets the values read back from the written file.

Units. Both compute outgoing radiance `sum/integral f_r cos E` in the probe's units; no
tone mapping, linear RGB, no spectral upsampling (RGB variant; the `rgb` reflectance
texture and the envmap store RGB as given).

Noise. Each image is the mean of `passes` independent renders (seeds 0..passes-1), each
with `spp` samples per pixel at the pixel centre; the per-pixel standard error of that mean
is std(passes, ddof = 1)/sqrt(passes), stored as `NAME.stderr.exr`. Directional-light
scenes are noise-free (a delta light, a delta camera sample): their stderr is 0 and only
f32 rounding separates the renderers' values.
"""

import argparse
import hashlib
import json
import math
import os
import sys
import time

import numpy as np

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
OUT = os.path.join(ROOT, "tests", "data", "peer")

# Scene parameters, shared with tests/peer.rs through the JSON files.
WIDTH = HEIGHT = 64
CAMERA = {"position": [0.0, 0.8, 4.0], "target": [0.0, 0.0, 0.0], "up": [0.0, 1.0, 0.0],
          "fov_y_deg": 35.0}
MATERIALS = {
    "lambert": {"kind": "lambert", "albedo": [0.8, 0.55, 0.3]},
    # brdfkit src/brdf/blinn_phong.rs: f = kd/pi + ks (n+8)/(8 pi) (n.h)^n.
    "blinn": {"kind": "blinn-phong", "kd": [0.3, 0.2, 0.1], "ks": [0.5, 0.5, 0.5],
              "exponent": 20.0},
}
# Directional light: to_light is the direction from the surface towards the light.
DIRECTIONAL = {"to_light": [0.6, 0.5, 0.62], "irradiance": [3.0, 2.5, 2.0]}
PROBES = ["city", "studio", "sky"]
PROBE_SIZE = (128, 64)


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def probe_row_solid_angles(width, height):
    """Exact solid angle of one texel per row (brdfkit conventions::probe_texel_solid_angle)."""
    rows = np.arange(height, dtype=np.float64)
    top, bottom = np.pi * rows / height, np.pi * (rows + 1) / height
    return (2.0 * np.pi / width) * (np.cos(top) - np.cos(bottom))


def load_clean_probe(mi, path):
    """The probe as brdfkit's loader sees it: linear RGB, negative channels clamped to 0."""
    bmp = mi.Bitmap(path).convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False)
    a = np.array(bmp, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        sys.exit(f"{path}: non-finite texels (brdfkit refuses them by default)")
    negative = int(np.count_nonzero(np.any(a < 0, axis=2)))
    return np.maximum(a, 0.0), negative


def downsample(a, width, height):
    """Solid-angle-weighted box filter to width x height (integer factors); power-preserving."""
    h, w, _ = a.shape
    fy, fx = h // height, w // width
    assert fy * height == h and fx * width == w, "probe size must be a multiple"
    omega = probe_row_solid_angles(w, h)[:, None, None]
    weighted = (a * omega).reshape(height, fy, width, fx, 3).sum(axis=(1, 3))
    area = (omega[:, 0, 0] * fx).reshape(height, fy).sum(axis=1)[:, None, None]
    return weighted / area


def upsample_for_mitsuba(a, k):
    """The piecewise-constant probe `a` (brdfkit grid) on Mitsuba's sample grid, k times finer.

    Columns: kW samples at u = (c + 1/2)/(kW) -> texel floor(c / k). Rows: kH + 1 samples at
    v = m/(kH) -> texel floor(m / k), or the mean of the two texels when m is a multiple of k
    strictly inside (the sample sits on a texel edge). See the module doc.
    """
    h, w, _ = a.shape
    cols = np.arange(k * w) // k
    rows = []
    for m in range(k * h + 1):
        if m % k == 0 and 0 < m < k * h:
            rows.append(0.5 * (a[m // k - 1] + a[m // k]))
        else:
            rows.append(a[min(m // k, h - 1)])
    return np.stack(rows)[:, cols, :]


def check_envmap_convention(mi, dr):
    """Evaluates a 4x3 envmap and asserts the convention stated in the module doc."""
    w, h = 4, 3
    a = np.zeros((h, w, 3), np.float32)
    a[:, :, 0] = np.arange(w)[None, :] + 1
    a[:, :, 1] = np.arange(h)[:, None] + 1
    em = mi.load_dict({"type": "envmap", "bitmap": mi.Bitmap(a)})

    def ev(u, v):
        th, ph = v * np.pi, u * 2 * np.pi
        d = mi.Vector3f(float(np.sin(ph) * np.sin(th)), float(np.cos(th)),
                        float(-np.cos(ph) * np.sin(th)))
        si = dr.zeros(mi.SurfaceInteraction3f)
        si.wi = -d
        return np.array(em.eval(si)).ravel()

    # Column c centred at u = (c + 1/2)/W; row r at v = r/(H - 1).
    for c in range(w):
        assert abs(ev((c + 0.5) / w, 0.5)[0] - (c + 1)) < 1e-4, "envmap column convention"
    for r in range(h):
        assert abs(ev(0.125, r / (h - 1))[1] - (r + 1)) < 1e-4, "envmap row convention"
    # u = 1/4 faces +x in Mitsuba's local frame: with W = 4 that is the edge between the
    # centres of columns 0 and 1 (values 1 and 2), so bilinear interpolation gives 1.5.
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(-1.0, 0.0, 0.0)
    assert abs(np.array(em.eval(si)).ravel()[0] - 1.5) < 1e-4


def register_blinn_phong(mi, dr):
    """brdfkit's energy-normalised Blinn-Phong (src/brdf/blinn_phong.rs) as a Mitsuba BSDF.

    f_r(wi, wo) = kd/pi + ks (n + 8)/(8 pi) (n.h)^n, h = normalize(wi + wo), zero unless
    both directions are above the horizon. Mitsuba's `eval` returns f_r cos(theta_o) (wo =
    towards the light in Mitsuba's naming). Sampling: with probability 1/2 cosine-weighted,
    else the half vector from pdf_h = (n + 1)/(2 pi) cos^n(theta_h) reflected about h
    (pdf_wo = pdf_h / (4 |wo.h|)); the pdf is the mixture, so the estimator is unbiased
    whatever the split (checked by `check_blinn_phong_sampling`).
    """

    class BlinnPhong(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.kd = mi.Color3f(props["kd"])
            self.ks = mi.Color3f(props["ks"])
            self.n = mi.Float(props["exponent"])
            flags = (mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.GlossyReflection
                     | mi.BSDFFlags.FrontSide)
            self.m_flags = flags
            self.m_components = [flags]

        def _f_cos(self, wi, wo, active):
            ci, co = mi.Frame3f.cos_theta(wi), mi.Frame3f.cos_theta(wo)
            h = dr.normalize(wi + wo)
            nh = dr.maximum(mi.Frame3f.cos_theta(h), 0.0)
            spec = (self.n + 8.0) / (8.0 * dr.pi) * dr.power(nh, self.n)
            f = self.kd * dr.inv_pi + self.ks * spec
            ok = active & (ci > 0) & (co > 0)
            return dr.select(ok, f * co, 0.0)

        def _pdf(self, wi, wo, active):
            ci, co = mi.Frame3f.cos_theta(wi), mi.Frame3f.cos_theta(wo)
            h = dr.normalize(wi + wo)
            nh = dr.maximum(mi.Frame3f.cos_theta(h), 0.0)
            pdf_h = (self.n + 1.0) * dr.inv_two_pi * dr.power(nh, self.n)
            pdf_spec = pdf_h / (4.0 * dr.maximum(dr.abs(dr.dot(wo, h)), 1e-12))
            pdf = 0.5 * co * dr.inv_pi + 0.5 * pdf_spec
            return dr.select(active & (ci > 0) & (co > 0), pdf, 0.0)

        def sample(self, ctx, si, sample1, sample2, active=True):
            wi = si.wi
            diffuse = sample1 < 0.5
            wo_d = mi.warp.square_to_cosine_hemisphere(sample2)
            cos_h = dr.power(sample2.x, 1.0 / (self.n + 1.0))
            sin_h = dr.safe_sqrt(1.0 - cos_h * cos_h)
            sp, cp = dr.sincos(dr.two_pi * sample2.y)
            h = mi.Vector3f(sin_h * cp, sin_h * sp, cos_h)
            wo_s = 2.0 * dr.dot(wi, h) * h - wi
            wo = dr.select(diffuse, wo_d, wo_s)
            bs = dr.zeros(mi.BSDFSample3f)
            bs.wo = wo
            bs.pdf = self._pdf(wi, wo, active)
            bs.eta = 1.0
            bs.sampled_type = dr.select(diffuse, mi.UInt32(+mi.BSDFFlags.DiffuseReflection),
                                        mi.UInt32(+mi.BSDFFlags.GlossyReflection))
            bs.sampled_component = mi.UInt32(0)
            ok = active & (bs.pdf > 0)
            value = dr.select(ok, self._f_cos(wi, wo, active) / dr.maximum(bs.pdf, 1e-30), 0.0)
            return bs, value

        def eval(self, ctx, si, wo, active=True):
            return self._f_cos(si.wi, wo, active)

        def pdf(self, ctx, si, wo, active=True):
            return self._pdf(si.wi, wo, active)

        def eval_pdf(self, ctx, si, wo, active=True):
            return self._f_cos(si.wi, wo, active), self._pdf(si.wi, wo, active)

        def traverse(self, callback):
            pass

        def parameters_changed(self, keys):
            pass

        def to_string(self):
            return "BrdfkitBlinnPhong"

    mi.register_bsdf("brdfkit_blinn_phong", lambda props: BlinnPhong(props))


def check_blinn_phong_sampling(mi, dr, mat):
    """Directional albedo two ways: E[eval/pdf] over the sampler and a deterministic
    quadrature of eval over the hemisphere; they must agree (sample/pdf consistency)."""
    bsdf = mi.load_dict({"type": "brdfkit_blinn_phong", "kd": mat["kd"], "ks": mat["ks"],
                         "exponent": mat["exponent"]})
    n = 1 << 20
    ctx = mi.BSDFContext()
    for theta in (0.0, 0.7, 1.3):
        si = dr.zeros(mi.SurfaceInteraction3f, n)
        si.wi = mi.Vector3f(math.sin(theta), 0.0, math.cos(theta))
        sampler = mi.load_dict({"type": "independent"})
        sampler.seed(7, n)
        _, w = bsdf.sample(ctx, si, sampler.next_1d(), sampler.next_2d())
        mc = np.array(w).mean(axis=1) if np.array(w).ndim == 2 else np.array(w).mean(axis=0)
        # Quadrature: midpoint in (cos theta_o, phi), 512 x 1024.
        mu = (np.arange(512) + 0.5) / 512
        ph = (np.arange(1024) + 0.5) / 1024 * 2 * np.pi
        MU, PH = np.meshgrid(mu, ph, indexing="ij")
        s = np.sqrt(1 - MU ** 2)
        wo = np.stack([s * np.cos(PH), s * np.sin(PH), MU], -1).reshape(-1, 3)
        wi = np.array([math.sin(theta), 0.0, math.cos(theta)])
        hv = wo + wi
        hv /= np.linalg.norm(hv, axis=1, keepdims=True)
        nn = mat["exponent"]
        f = (np.array(mat["kd"])[None] / np.pi
             + np.array(mat["ks"])[None] * (nn + 8) / (8 * np.pi) * (hv[:, 2:3] ** nn))
        quad = (f * wo[:, 2:3]).sum(0) * (1.0 / 512) * (2 * np.pi / 1024)
        assert np.allclose(mc, quad, rtol=5e-3), f"Blinn-Phong sampling at {theta}: {mc} {quad}"


def look_at(mi, cam):
    return mi.ScalarTransform4f().look_at(origin=cam["position"], target=cam["target"],
                                          up=cam["up"])


def make_scene(mi, material, emitter):
    if material["kind"] == "lambert":
        bsdf = {"type": "diffuse", "reflectance": {"type": "rgb", "value": material["albedo"]}}
    else:
        bsdf = {"type": "brdfkit_blinn_phong", "kd": material["kd"], "ks": material["ks"],
                "exponent": material["exponent"]}
    return mi.load_dict({
        "type": "scene",
        "sensor": {
            "type": "perspective", "fov": CAMERA["fov_y_deg"], "fov_axis": "y",
            "to_world": look_at(mi, CAMERA), "near_clip": 0.01,
            "film": {"type": "hdrfilm", "width": WIDTH, "height": HEIGHT,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": bsdf},
        "emitter": emitter,
    })


def envmap_emitter(mi, data):
    # brdfkit_world = diag(-1, 1, -1) mitsuba_local (module doc), written exactly.
    m = np.diag([-1.0, 1.0, -1.0, 1.0])
    return {"type": "envmap", "bitmap": mi.Bitmap(data.astype(np.float32)),
            "to_world": mi.ScalarTransform4f(m)}


def directional_emitter(light):
    return {"type": "directional", "direction": [-x for x in light["to_light"]],
            "irradiance": {"type": "rgb", "value": light["irradiance"]}}


def render_centres(mi, dr, scene, spp, seed):
    """One pass: `spp` samples through every pixel centre, Mitsuba's `direct` integrator."""
    integrator = mi.load_dict({"type": "direct", "hide_emitters": True})
    sensor = scene.sensors()[0]
    n = WIDTH * HEIGHT * spp
    idx = dr.arange(mi.UInt32, n) // spp
    x = mi.Float(idx % WIDTH) + 0.5
    y = mi.Float(idx // WIDTH) + 0.5
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n)
    ray, weight = sensor.sample_ray(0.0, 0.5, mi.Point2f(x / WIDTH, y / HEIGHT),
                                    mi.Point2f(0.5, 0.5))
    rd = mi.RayDifferential3f(ray)
    spec, valid, _ = integrator.sample(scene, sampler, rd)
    spec = weight * spec
    a = np.array(spec)  # (3, n)
    if a.shape[0] != 3:
        a = a.T
    return a.reshape(3, HEIGHT, WIDTH, spp).mean(axis=3).transpose(1, 2, 0)


def render_passes(mi, dr, scene, spp, passes, seed0):
    imgs = np.stack([render_centres(mi, dr, scene, spp, seed0 + s) for s in range(passes)])
    mean = imgs.mean(axis=0)
    stderr = imgs.std(axis=0, ddof=1) / math.sqrt(passes) if passes > 1 else np.zeros_like(mean)
    return mean, stderr


def write_exr(mi, path, img):
    mi.Bitmap(np.ascontiguousarray(img, dtype=np.float32)).write(path)


def noise_summary(mean, stderr):
    inside = mean.sum(axis=2) > 0
    m = mean[inside]
    s = stderr[inside]
    return {
        "pixels_nonzero": int(inside.sum()),
        "image_mean": float(mean.mean()),
        "mean_relative_stderr": float((s / np.maximum(m, 1e-30)).mean()),
        "max_relative_stderr": float((s / np.maximum(m, 1e-30)).max()),
        "stderr_of_image_mean": float(np.sqrt((stderr ** 2).sum()) / mean.size),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variant", default="llvm_ad_rgb")
    ap.add_argument("--spp", type=int, default=4096, help="samples per pixel per pass")
    ap.add_argument("--passes", type=int, default=64, help="independent passes (seeds)")
    ap.add_argument("--upsample", type=int, default=8, help="k of the envmap resampling")
    ap.add_argument("--only", action="append", help="scene name(s) to render")
    ap.add_argument("--naive-passes", type=int, default=8,
                    help="passes of the naive-envmap measurement (same spp per pass)")
    ap.add_argument("--skip-naive", action="store_true",
                    help="do not measure the naive envmap (probe given to Mitsuba as is)")
    args = ap.parse_args()

    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    check_envmap_convention(mi, dr)
    register_blinn_phong(mi, dr)
    check_blinn_phong_sampling(mi, dr, MATERIALS["blinn"])
    os.makedirs(OUT, exist_ok=True)

    common = {
        "generator": "scripts/peer/render_peer.py",
        "mitsuba_version": mi.__version__,
        "drjit_version": dr.__version__,
        "variant": args.variant,
        "integrator": "direct (emitter_samples = 1, bsdf_samples = 1, MIS), hide_emitters",
        "pixel_sampling": "every sample through the pixel centre (x + 1/2, y + 1/2)",
        "width": WIDTH, "height": HEIGHT, "camera": CAMERA,
        "sphere": {"center": [0.0, 0.0, 0.0], "radius": 1.0, "shape": "mitsuba analytic sphere"},
    }
    scenes = []
    for mat in ("lambert", "blinn"):
        for p in PROBES:
            scenes.append((f"{mat}-{p}", mat, p))
        scenes.append((f"{mat}-directional", mat, None))
    if args.only:
        scenes = [s for s in scenes if s[0] in args.only]

    probes = {}
    for name, mat, probe in scenes:
        if probe is None or probe in probes:
            continue
        src = os.path.join(ROOT, "assets", "probes", f"{probe}.exr")
        full, negative = load_clean_probe(mi, src)
        small = downsample(full, *PROBE_SIZE)
        rel = f"probe-{probe}-{PROBE_SIZE[0]}x{PROBE_SIZE[1]}.exr"
        path = os.path.join(OUT, rel)
        write_exr(mi, path, small)
        back, neg2 = load_clean_probe(mi, path)  # exactly what brdfkit will load
        assert neg2 == 0 and np.array_equal(back, small.astype(np.float32).astype(np.float64))
        power = (small * probe_row_solid_angles(*PROBE_SIZE)[:, None, None]).sum((0, 1))
        power_full = (full * probe_row_solid_angles(full.shape[1], full.shape[0])[:, None, None]
                      ).sum((0, 1))
        probes[probe] = {
            "data": back, "file": rel, "source": f"assets/probes/{probe}.exr",
            "source_sha256": sha256(src), "sha256": sha256(path),
            "source_negative_texels_clamped": negative,
            "downsample": f"{full.shape[1]}x{full.shape[0]} -> {PROBE_SIZE[0]}x{PROBE_SIZE[1]}, "
                          "solid-angle-weighted 4x4 box",
            "total_power_rgb": power.tolist(),
            "total_power_rgb_source": power_full.tolist(),
        }

    for name, mat, probe in scenes:
        t0 = time.time()
        material = MATERIALS[mat]
        meta = dict(common)
        meta.update({"name": name, "material": material, "image": f"{name}.exr",
                     "stderr_image": f"{name}.stderr.exr"})
        if probe is None:
            scene = make_scene(mi, material, directional_emitter(DIRECTIONAL))
            # Deterministic: one pass of one sample (a delta light through a delta camera sample).
            mean = render_centres(mi, dr, scene, 1, 0)
            stderr = np.zeros_like(mean)
            meta.update({"light": {"kind": "directional", **DIRECTIONAL},
                         "spp_per_pass": 1, "passes": 1, "seeds": [0],
                         "noise_note": "noise-free: delta light, pixel-centre camera ray"})
        else:
            pr = probes[probe]
            data = upsample_for_mitsuba(pr["data"], args.upsample)
            scene = make_scene(mi, material, envmap_emitter(mi, data))
            seeds = list(range(args.passes))
            mean, stderr = render_passes(mi, dr, scene, args.spp, args.passes, 0)
            meta.update({
                "light": {"kind": "env", "probe": pr["file"], "probe_sha256": pr["sha256"],
                          "source": pr["source"], "source_sha256": pr["source_sha256"],
                          "source_negative_texels_clamped": pr["source_negative_texels_clamped"],
                          "downsample": pr["downsample"],
                          "total_power_rgb": pr["total_power_rgb"],
                          "total_power_rgb_source": pr["total_power_rgb_source"],
                          "mitsuba_envmap": f"piecewise-constant probe resampled {args.upsample}x "
                                            f"({data.shape[1]}x{data.shape[0]}), see script doc",
                          "to_world": "diag(-1, 1, -1): 180 degrees about +y"},
                "spp_per_pass": args.spp, "passes": args.passes, "seeds": seeds,
                "spp_total": args.spp * args.passes,
            })
            if not args.skip_naive:
                # What the fair resampling buys: the probe handed to Mitsuba as is.
                naive_scene = make_scene(mi, material, envmap_emitter(mi, pr["data"]))
                nm, ns = render_passes(mi, dr, naive_scene, args.spp, args.naive_passes, 1000)
                inside = mean.sum(axis=2) > 0
                z = (nm - mean)[inside] / np.sqrt(ns[inside] ** 2 + stderr[inside] ** 2 + 1e-30)
                meta["naive_envmap"] = {
                    "what": "same scene, Mitsuba given the 128x64 probe directly (bilinear, "
                            "rows at v = r/(H-1)), seeds 1000..",
                    "passes": args.naive_passes, "spp_per_pass": args.spp,
                    "ratio_of_means_naive_over_fair": float(nm.mean() / mean.mean()),
                    "max_abs_relative_pixel_difference": float(
                        (np.abs(nm - mean)[inside] / np.maximum(mean[inside], 1e-30)).max()),
                    "rms_z_pixel_difference": float(np.sqrt((z ** 2).mean())),
                    "max_abs_z": float(np.abs(z).max()),
                }
        write_exr(mi, os.path.join(OUT, meta["image"]), mean)
        write_exr(mi, os.path.join(OUT, meta["stderr_image"]), stderr)
        meta["noise"] = noise_summary(mean, stderr)
        meta["render_seconds"] = round(time.time() - t0, 1)
        with open(os.path.join(OUT, f"{name}.json"), "w") as f:
            json.dump(meta, f, indent=2)
            f.write("\n")
        print(name, json.dumps(meta["noise"]), meta.get("naive_envmap", ""), f"{meta['render_seconds']} s",
              flush=True)


if __name__ == "__main__":
    main()
