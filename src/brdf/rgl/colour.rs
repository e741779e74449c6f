//! Spectral samples to linear sRGB: how a spectral RGL file becomes the renderer's RGB.
//!
//! Observer: the CIE 1931 2-degree colour matching functions; illuminant: CIE D65; both
//! tabulated from 360 to 830 nm in 1 nm steps (`cie1931_d65.csv`, the CIE tables). A
//! reflectance spectrum `S` (here a BRDF value per wavelength, 1/sr) becomes
//!
//! `XYZ = sum_l S(l) D65(l) cmf(l) / sum_l D65(l) y_bar(l)` (1 nm steps, trapezoid rule),
//! `RGB = M XYZ` with `M` the XYZ-to-linear-sRGB matrix of IEC 61966-2-1 (D65 white),
//!
//! then each channel is divided by that of a spectrally flat `S = 1`, so a flat spectrum
//! is exactly grey (the matrix alone gives it to ~1e-3): the colour a white D65 light
//! shows, which is what a spectral renderer (Mitsuba 3's spectral variants) shows under
//! an emitter given in RGB as white. Between the file's wavelengths the spectrum is
//! linear, and constant beyond the first and last, as the published readers interpolate
//! it. Linear in `S`, so it is applied once per table node at load
//! ([`srgb_weights`]): interpolating the RGB table equals converting the interpolated
//! spectrum.

/// XYZ to linear sRGB (IEC 61966-2-1, D65 white), row-major.
pub const XYZ_TO_SRGB: [[f64; 3]; 3] = [
    [3.2404542, -1.5371385, -0.4985314],
    [-0.9692660, 1.8760108, 0.0415560],
    [0.0556434, -0.2040259, 1.0572252],
];

/// The CIE table: `(nm, x_bar, y_bar, z_bar, d65)` rows, 360 to 830 nm in 1 nm steps.
pub fn cie_table() -> Vec<[f64; 5]> {
    include_str!("cie1931_d65.csv")
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("nm"))
        .map(|l| {
            let mut row = [0.0; 5];
            for (k, v) in l.split(',').enumerate() {
                row[k] = v.parse().expect("cie1931_d65.csv is well formed");
            }
            row
        })
        .collect()
}

/// Weight of each of `wavelengths` (nm, strictly increasing) in each linear sRGB channel
/// (module doc): `rgb[c] = sum_k w[k][c] S_k`.
pub fn srgb_weights(wavelengths: &[f64]) -> Vec<[f64; 3]> {
    let table = cie_table();
    let n = wavelengths.len();
    let mut xyz = vec![[0.0f64; 3]; n];
    let mut norm = 0.0;
    let last = table.len() - 1;
    for (j, row) in table.iter().enumerate() {
        let dl = if j == 0 || j == last { 0.5 } else { 1.0 };
        let (l, d65) = (row[0], row[4]);
        norm += dl * d65 * row[2];
        // The hat functions of the nodes around l (constant beyond the ends).
        let i = wavelengths[1..n.saturating_sub(1)]
            .iter()
            .filter(|&&v| v < l)
            .count();
        let (w0, w1) = if n == 1 {
            (1.0, 0.0)
        } else {
            let t = ((l - wavelengths[i]) / (wavelengths[i + 1] - wavelengths[i])).clamp(0.0, 1.0);
            (1.0 - t, t)
        };
        for c in 0..3 {
            let v = dl * d65 * row[1 + c];
            xyz[i][c] += w0 * v;
            if n > 1 {
                xyz[i + 1][c] += w1 * v;
            }
        }
    }
    let mut rgb: Vec<[f64; 3]> = xyz
        .iter()
        .map(|x| {
            let mut o = [0.0; 3];
            for (c, row) in XYZ_TO_SRGB.iter().enumerate() {
                o[c] = (row[0] * x[0] + row[1] * x[1] + row[2] * x[2]) / norm;
            }
            o
        })
        .collect();
    let mut white = [0.0; 3];
    for w in &rgb {
        for c in 0..3 {
            white[c] += w[c];
        }
    }
    for w in &mut rgb {
        for c in 0..3 {
            w[c] /= white[c];
        }
    }
    rgb
}
