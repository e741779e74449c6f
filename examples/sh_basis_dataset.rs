//! Writes an SH data set whose every view texel holds one real SH basis function:
//! `f_r cos(polar_i) = Y_l^m(wi)` in all three colours. Rendered under a directional light,
//! the image shows `Y_l^m` of the light's local direction over the lit hemisphere, the
//! function the thesis plots in Fig. 2.5 (negative values are black in the PNG).
//! Makes `golden/sh-basis-y2-2.exr`:
//! `cargo run --example sh_basis_dataset -- 2 2 golden/sh-basis-y2-2.exr`
use brdfkit::sh::{sh_index, write_sh_dataset, ShDataset};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: sh_basis_dataset L M OUT.exr (0 <= L < 10, |M| <= L)";
    let [l, m, out] = args.as_slice() else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    let (Ok(l), Ok(m)) = (l.parse::<usize>(), m.parse::<i32>()) else {
        eprintln!("{usage}");
        std::process::exit(2);
    };
    if l >= 10 || m.unsigned_abs() as usize > l {
        eprintln!("{usage}");
        std::process::exit(2);
    }
    let provenance = format!("examples/sh_basis_dataset: Y_{l}^{m} in every view texel");
    let mut ds = ShDataset::zeros(1, 1, l + 1, true, provenance).expect("valid grid");
    for c in 0..3 {
        ds.texel_mut(0, 0, c)[sh_index(l, m)] = 1.0;
    }
    if let Err(e) = write_sh_dataset(std::path::Path::new(out), &ds) {
        eprintln!("{e}");
        std::process::exit(1);
    }
}
