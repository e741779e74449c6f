#!/usr/bin/env python3
"""Peer images of brdfkit's RGL test materials, rendered by Mitsuba 3's `measured` BSDF.

The RGL `.bsdf` files are brdfkit's analytic test materials (src/brdf/rgl/samples.rs),
written by `cargo run --release --example write_rgl -- DIR` (this script runs it). Mitsuba
reads each file with its own reader and renders it on the unit sphere of
scripts/peer/render_peer.py (same camera, pixel-centre rays, `direct` integrator, probe
orientation and resampling: that script's module doc; its functions are reused here)
under one directional light and under the downsampled `city` probe; the spectral file also
under a white directional light. tests/integration/peer_rgl.rs renders the same scenes with
brdfkit's converged reference and compares. CI does not need Mitsuba: the images are stored
in tests/data/peer/ (64x64, with a JSON file each recording the Mitsuba version, variant,
sample counts, seeds, measured noise and the SHA-256 of the material file).

Usage (repository root; Mitsuba 3 from PyPI, `pip install mitsuba numpy`; the LLVM
variants need libLLVM >= 16, see render_peer.py):

    python3 scripts/peer/render_rgl_peer.py            # all scenes, writes tests/data/peer/
    python3 scripts/peer/render_rgl_peer.py --only rgl-blinn-rgb-city --passes 4

Variants: an RGB file (`rgb` field) needs an RGB variant (`llvm_ad_rgb`), a spectral file
(`wavelengths` + `spectra`) a spectral one (`llvm_ad_spectral`): Mitsuba's `measured`
plugin refuses the other combination. The script runs itself once per variant.

Spectral scenes. The emitters' RGB values become spectra (Mitsuba's `d65` texture: the
upsampled RGB times the D65 illuminant, so RGB white is D65, as brdfkit's spectral-to-sRGB
conversion assumes, src/brdf/rgl/colour.rs), each camera sample draws its wavelengths, and
the radiance is converted to linear sRGB with `spectrum_to_srgb`, as Mitsuba's film does.
Two differences remain, both recorded in the JSON (`spectral`) so the test can state them
exactly: (1) Mitsuba's camera and film turn an RGB-white emitter into 0.99999, 0.99988,
0.99980 (`film_white`: its D65 normalisation, CIE tables and XYZ-to-sRGB matrix agree to
~2e-4), where brdfkit white-balances to exactly 1; (2) under a coloured light Mitsuba multiplies spectra (the file's by the
light's) and brdfkit RGB (the file's converted colour by the light's RGB), which differ for
a saturated reflectance: for the warm directional light the script records the film's
sRGB of the light's spectrum times the material's diffuse spectrum and times 1
(`film_light_times_kd`, `film_light`), from which the test predicts the difference per
pixel. The `white` scene has neither (1 divided out, no (2)): there the two renderers must
agree within the noise. Under `city` (2) is left as a stated bound.

Shading frame. Mitsuba's sphere has its tangent along increasing longitude about the
sphere's axis; brdfkit's tangent is world up (+y) projected onto the tangent plane
(src/conventions/frame.rs: `t = (-n.x n.y, s, -n.z n.y) / s`, `s = sqrt(n.x^2 + n.z^2)`,
`b = n x t`). For an anisotropic material the frames must agree, so the `measured` BSDF is
wrapped (`RglFramed`) to see its directions in brdfkit's frame: eval, pdf and sample turn
`wi`, `wo` into brdfkit's local coordinates and the sampled direction back. The normal is
shared, so cosines are unchanged.
"""

import argparse
import hashlib
import json
import math
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import render_peer as rp  # noqa: E402

ROOT = rp.ROOT
OUT = rp.OUT
MATERIALS = {
    "blinn-rgb": "llvm_ad_rgb",
    "aniso-rgb": "llvm_ad_rgb",
    "blinn-spectral": "llvm_ad_spectral",
}
PROBE = "city"
DIRECTIONAL = rp.DIRECTIONAL
# The spectral file also under a white light: there brdfkit's spectra-to-sRGB conversion is
# exact against Mitsuba's spectral render up to the film's white (`film_white`).
WHITE = {"to_light": DIRECTIONAL["to_light"], "irradiance": [1.0, 1.0, 1.0]}
SCENE_KINDS = {
    "blinn-rgb": ("directional", PROBE),
    "aniso-rgb": ("directional", PROBE),
    "blinn-spectral": ("directional", "white", PROBE),
}


def register_framed(mi, dr):
    class RglFramed(mi.BSDF):
        def __init__(self, props):
            mi.BSDF.__init__(self, props)
            self.inner = props["inner"]
            self.m_flags = self.inner.flags()
            self.m_components = [self.inner.flags()]

        def _frame(self, si):
            n = si.sh_frame.n
            s = dr.sqrt(dr.maximum(n.x * n.x + n.z * n.z, 1e-30))
            t = mi.Vector3f(-n.x * n.y / s, s, -n.z * n.y / s)
            b = dr.cross(n, t)
            return t, b, n

        def _to_b(self, si, v):
            w = si.sh_frame.to_world(v)
            t, b, n = self._frame(si)
            return mi.Vector3f(dr.dot(w, t), dr.dot(w, b), dr.dot(w, n))

        def _from_b(self, si, v):
            t, b, n = self._frame(si)
            w = t * v.x + b * v.y + n * v.z
            return si.sh_frame.to_local(w)

        def eval(self, ctx, si, wo, active=True):
            old = mi.Vector3f(si.wi)
            si.wi = self._to_b(si, old)
            v = self.inner.eval(ctx, si, self._to_b(si, wo), active)
            si.wi = old
            return v

        def pdf(self, ctx, si, wo, active=True):
            old = mi.Vector3f(si.wi)
            si.wi = self._to_b(si, old)
            p = self.inner.pdf(ctx, si, self._to_b(si, wo), active)
            si.wi = old
            return p

        def eval_pdf(self, ctx, si, wo, active=True):
            return self.eval(ctx, si, wo, active), self.pdf(ctx, si, wo, active)

        def sample(self, ctx, si, sample1, sample2, active=True):
            old = mi.Vector3f(si.wi)
            si.wi = self._to_b(si, old)
            bs, w = self.inner.sample(ctx, si, sample1, sample2, active)
            si.wi = old
            bs.wo = self._from_b(si, bs.wo)
            return bs, w

        def traverse(self, callback):
            pass

        def parameters_changed(self, keys):
            pass

        def to_string(self):
            return "RglFramed"

    mi.register_bsdf("rgl_framed", lambda props: RglFramed(props))


def make_scene(mi, path, emitter):
    bsdf = {"type": "rgl_framed", "inner": {"type": "measured", "filename": path}}
    cam = rp.CAMERA
    return mi.load_dict({
        "type": "scene",
        "sensor": {
            "type": "perspective", "fov": cam["fov_y_deg"], "fov_axis": "y",
            "to_world": rp.look_at(mi, cam), "near_clip": 0.01,
            "film": {"type": "hdrfilm", "width": rp.WIDTH, "height": rp.HEIGHT,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
        },
        "sphere": {"type": "sphere", "center": [0.0, 0.0, 0.0], "radius": 1.0, "bsdf": bsdf},
        "emitter": emitter,
    })


def film_rgb(mi, dr, sensor, spectrum, n=1 << 20):
    """The linear sRGB Mitsuba's camera and film make of a radiance spectrum on average:
    `spectrum(wavelengths)` at the camera's own wavelength samples (`sample_wavelengths`,
    weight included) on a stratified grid of `n` points, converted by `spectrum_to_srgb`
    as `render_centres` converts each sample. A quadrature of the estimator's mean."""
    u = (dr.arange(mi.Float, n) + 0.5) / n
    si = dr.zeros(mi.SurfaceInteraction3f)
    wav, weight = sensor.sample_wavelengths(si, u)
    si.wavelengths = wav
    rgb = np.array(mi.spectrum_to_srgb(weight * spectrum(si, wav), wav))
    if rgb.shape[0] != 3:
        rgb = rgb.T
    return rgb.mean(axis=1)


def light_spectrum(mi, rgb):
    """An emitter's spectrum for an RGB value in a spectral variant: Mitsuba's `d65`
    texture (the upsampled RGB times the D65 illuminant), what `directional` and `envmap`
    make of RGB."""
    tex = mi.load_dict({"type": "d65", "color": rgb})
    return lambda si, wav: tex.eval(si)


def spectral_kd_nodes():
    """The diffuse spectrum of `blinn-spectral` at the file's wavelengths: the formula of
    src/brdf/rgl/samples.rs (`spectral_kd`, 370 to 830 nm in 20 nm steps), which the test
    checks the recorded values against."""
    waves = 370.0 + 20.0 * np.arange(24)
    return waves, 0.05 + 0.5 * np.exp(-(((waves - 610.0) / 50.0) ** 2))


def spectral_record(mi, dr, scene, light):
    """What the test needs to predict the spectral file's difference under `light`
    (tests/integration/peer_rgl.rs): Mitsuba's film white (an RGB-white emitter, D65),
    and, for the test material's diffuse spectrum `kd` (`spectral_kd_nodes`, linear
    between the file's wavelengths and constant beyond, as the `measured` plugin
    interpolates) and its flat specular part, the film's sRGB of the light's spectrum times
    `kd` and times 1."""
    sensor = scene.sensors()[0]
    white = film_rgb(mi, dr, sensor, light_spectrum(mi, [1.0, 1.0, 1.0]))
    waves, kd = spectral_kd_nodes()
    e = light_spectrum(mi, light["irradiance"])

    def e_kd(si, wav):
        w = np.array(wav)
        if w.shape[0] != 4:
            w = w.T
        k = np.interp(w, waves, kd)
        return e(si, wav) * mi.Spectrum(k)
    return {
        "film_white": white.tolist(),
        "film_light_times_kd": film_rgb(mi, dr, sensor, e_kd).tolist(),
        "film_light": film_rgb(mi, dr, sensor, e).tolist(),
        "kd_wavelengths": waves.tolist(), "kd": kd.tolist(),
    }


def render_centres(mi, dr, scene, spp, seed, spectral):
    """One pass: `spp` samples through every pixel centre (render_peer.render_centres), each
    camera sample with its own wavelengths in a spectral variant."""
    integrator = mi.load_dict({"type": "direct", "hide_emitters": True})
    sensor = scene.sensors()[0]
    w, h = rp.WIDTH, rp.HEIGHT
    n = w * h * spp
    idx = dr.arange(mi.UInt32, n) // spp
    x = mi.Float(idx % w) + 0.5
    y = mi.Float(idx // w) + 0.5
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, n)
    wav = sampler.next_1d() if spectral else mi.Float(0.5)
    ray, weight = sensor.sample_ray(0.0, wav, mi.Point2f(x / w, y / h), mi.Point2f(0.5, 0.5))
    spec, _, _ = integrator.sample(scene, sampler, mi.RayDifferential3f(ray))
    spec = weight * spec
    if spectral:
        rgb = mi.spectrum_to_srgb(spec, ray.wavelengths)
    else:
        rgb = spec
    a = np.array(rgb)
    if a.shape[0] != 3:
        a = a.T
    return a.reshape(3, h, w, spp).mean(axis=3).transpose(1, 2, 0)


def render_passes(mi, dr, scene, spp, passes, spectral):
    imgs = np.stack([render_centres(mi, dr, scene, spp, s, spectral) for s in range(passes)])
    mean = imgs.mean(axis=0)
    stderr = imgs.std(axis=0, ddof=1) / math.sqrt(passes) if passes > 1 else np.zeros_like(mean)
    return mean, stderr


def run_variant(args, variant):
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(variant)
    register_framed(mi, dr)
    spectral = "spectral" in variant
    files = os.path.abspath(args.files)
    probe_file = f"probe-{PROBE}-{rp.PROBE_SIZE[0]}x{rp.PROBE_SIZE[1]}.exr"
    probe, _ = rp.load_clean_probe(mi, os.path.join(OUT, probe_file))
    for mat, v in MATERIALS.items():
        if v != variant:
            continue
        path = os.path.join(files, f"{mat}.bsdf")
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()
        for scene_kind in SCENE_KINDS[mat]:
            name = f"rgl-{mat}-{scene_kind}"
            if args.only and name not in args.only:
                continue
            t0 = time.time()
            meta = {
                "generator": "scripts/peer/render_rgl_peer.py",
                "mitsuba_version": mi.__version__, "drjit_version": dr.__version__,
                "variant": variant,
                "bsdf": "measured (wrapped into brdfkit's shading frame, see script doc)",
                "integrator": "direct (emitter_samples = 1, bsdf_samples = 1, MIS), hide_emitters",
                "pixel_sampling": "every sample through the pixel centre (x + 1/2, y + 1/2)",
                "width": rp.WIDTH, "height": rp.HEIGHT, "camera": rp.CAMERA,
                "sphere": {"center": [0.0, 0.0, 0.0], "radius": 1.0,
                           "shape": "mitsuba analytic sphere"},
                "name": name, "material": {"kind": "rgl-file", "sample": mat,
                                           "writer": "cargo run --release --example write_rgl",
                                           "sha256": digest},
                "image": f"{name}.exr", "stderr_image": f"{name}.stderr.exr",
            }
            if scene_kind in ("directional", "white"):
                light = DIRECTIONAL if scene_kind == "directional" else WHITE
                scene = make_scene(mi, path, rp.directional_emitter(light))
                passes, spp = ((args.passes_directional, args.spp_directional) if spectral
                               else (1, 1))
                meta["light"] = {"kind": "directional", **light}
                if spectral:
                    meta["spectral"] = spectral_record(mi, dr, scene, light)
            else:
                data = rp.upsample_for_mitsuba(probe, args.upsample)
                scene = make_scene(mi, path, rp.envmap_emitter(mi, data))
                passes, spp = args.passes, args.spp
                meta["light"] = {"kind": "env", "probe": probe_file,
                                 "probe_sha256": rp.sha256(os.path.join(OUT, probe_file)),
                                 "mitsuba_envmap": f"piecewise-constant probe resampled "
                                                   f"{args.upsample}x, see render_peer.py",
                                 "to_world": "diag(-1, 1, -1): 180 degrees about +y"}
            if spectral and "spectral" not in meta:
                white = film_rgb(mi, dr, scene.sensors()[0], light_spectrum(mi, [1.0] * 3))
                meta["spectral"] = {"film_white": white.tolist()}
            mean, stderr = render_passes(mi, dr, scene, spp, passes, spectral)
            meta.update({"spp_per_pass": spp, "passes": passes, "seeds": list(range(passes)),
                         "spp_total": spp * passes})
            if passes == 1:
                meta["noise_note"] = "noise-free: delta light, pixel-centre camera ray, RGB"
            rp.write_exr(mi, os.path.join(OUT, meta["image"]), mean)
            rp.write_exr(mi, os.path.join(OUT, meta["stderr_image"]), stderr)
            meta["noise"] = rp.noise_summary(mean, stderr)
            meta["render_seconds"] = round(time.time() - t0, 1)
            with open(os.path.join(OUT, f"{name}.json"), "w") as f:
                json.dump(meta, f, indent=2)
                f.write("\n")
            print(name, json.dumps(meta["noise"]), f"{meta['render_seconds']} s", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--variant", help="run one variant only (the script runs both)")
    ap.add_argument("--files", default=os.path.join(ROOT, "target", "rgl-peer"),
                    help="directory of the .bsdf files (written there first)")
    ap.add_argument("--no-write", action="store_true", help="use the files as they are")
    ap.add_argument("--spp", type=int, default=1024, help="samples per pixel per pass (probe)")
    ap.add_argument("--spp-directional", type=int, default=128,
                    help="samples per pixel per pass (spectral directional)")
    ap.add_argument("--passes-directional", type=int, default=64,
                    help="independent passes (spectral directional: the test's z bounds "
                         "assume 64, Student's t with 63 degrees of freedom)")
    ap.add_argument("--passes", type=int, default=16, help="independent passes (seeds)")
    ap.add_argument("--upsample", type=int, default=8, help="k of the envmap resampling")
    ap.add_argument("--only", action="append", help="scene name(s) to render")
    args = ap.parse_args()
    if args.variant:
        run_variant(args, args.variant)
        return
    if not args.no_write:
        subprocess.run(["cargo", "run", "--release", "--example", "write_rgl", "--",
                        args.files], cwd=ROOT, check=True)
    for variant in sorted(set(MATERIALS.values())):
        cmd = [sys.executable, __file__, "--variant", variant, "--files", args.files,
               "--spp", str(args.spp), "--spp-directional", str(args.spp_directional),
               "--passes-directional", str(args.passes_directional),
               "--passes", str(args.passes), "--upsample", str(args.upsample)]
        for o in args.only or []:
            cmd += ["--only", o]
        subprocess.run(cmd, check=True)


if __name__ == "__main__":
    main()
