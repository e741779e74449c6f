//! Tests of the lane wrapper: every dispatch path computes the same lanes.

use super::*;

/// [`KernelPath::available`], after saying past libtest's capture (so a plain `cargo test`
/// shows it) each path `test` skips on this CPU, by name.
fn paths_run_by(test: &str) -> Vec<KernelPath> {
    use std::io::Write;
    for (path, needs) in KernelPath::unavailable() {
        let _ = writeln!(
            std::io::stderr(),
            "SKIPPED kernel path {}: lanes::tests::{test}: this CPU lacks {needs}",
            path.name()
        );
    }
    KernelPath::available()
}

struct Probe(Vec<f32>, Vec<f32>);
impl Kernel for Probe {
    type Out = (Vec<f32>, f32, u32, Vec<f32>);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Self::Out {
        let a = s.load(&self.0);
        let b = s.load(&self.1);
        let mut out = vec![0.0; 16];
        let r = (a * b + a - b).max(s.splat(-1.0)).min(s.splat(10.0));
        r.store(&mut out);
        let n = a.compress_store(a.gt_mask(s.zero()), &mut out, 8);
        let mut packed = out[8..8 + n].to_vec();
        packed.push(a.keep(0b1010_0101).sum());
        (
            out[..8].to_vec(),
            a.positive_part().sum(),
            b.gt_mask(a),
            packed,
        )
    }
}

#[test]
fn every_dispatch_path_computes_the_same_lanes() {
    let a = vec![1.0, -2.0, 3.0, -4.0, 5.0, 0.0, 7.0, -0.5];
    let b = vec![0.5, 1.0, -1.0, 2.0, 2.0, 3.0, 0.25, 1.0];
    let want = Dispatch::portable().run(Probe(a.clone(), b.clone()));
    for path in paths_run_by("every_dispatch_path_computes_the_same_lanes") {
        let got = Dispatch::choose(path)
            .unwrap()
            .run(Probe(a.clone(), b.clone()));
        assert_eq!(want, got, "{}", path.name());
    }
    let lanes: Vec<f32> = (0..8)
        .map(|i| (a[i] * b[i] + a[i] - b[i]).clamp(-1.0, 10.0))
        .collect();
    assert_eq!(want.0, lanes);
    assert_eq!(want.1, 16.0);
    assert_eq!(want.2, 0b1010_1010);
    assert_eq!(want.3, vec![1.0, 3.0, 5.0, 7.0, 3.5]);
}

struct Fused(f32, f32, f32);
impl Kernel for Fused {
    type Out = (f32, f32);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> (f32, f32) {
        let (a, b, c) = (s.splat(self.0), s.splat(self.1), s.splat(self.2));
        (a.mul_add(b, c).lane(3), a.neg_mul_add(b, c).lane(5))
    }
}

#[test]
fn mul_add_rounds_once_on_every_path() {
    // (1 + 2^-12)^2 = 1 + 2^-11 + 2^-24: the 2^-24 is lost if the product is rounded
    // before the add.
    let a = 1.0 + f32::powi(2.0, -12);
    let c = -(1.0 + f32::powi(2.0, -11));
    let want = (f32::powi(2.0, -24), -f32::powi(2.0, -24));
    assert_ne!(a * a + c, want.0, "the case must tell fused from unfused");
    for path in paths_run_by("mul_add_rounds_once_on_every_path") {
        let d = Dispatch::choose(path).unwrap();
        let got = d.run(Fused(a, a, c));
        assert_eq!(got.0, want.0, "{}: mul_add", path.name());
        let got = d.run(Fused(a, a, -c));
        assert_eq!(got.1, want.1, "{}: neg_mul_add", path.name());
    }
}

#[test]
fn auto_and_portable_always_have_a_path() {
    assert!(Dispatch::choose(KernelPath::Auto).is_some());
    assert_eq!(
        Dispatch::choose(KernelPath::Portable).map(Dispatch::path),
        Some(KernelPath::Portable)
    );
    assert!(KernelPath::available().contains(&KernelPath::Portable));
}

/// The same per-lane chain at the path's widest width ([`Isa::wide`]), split into halves
/// ([`Isa::half`]), and on eight lanes.
struct WideProbe(Vec<f32>, Vec<f32>);
impl Kernel for WideProbe {
    type Out = (usize, Vec<f32>, Vec<f32>, Vec<f32>);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Self::Out {
        let w = s.wide();
        let n = <S::Wide as Width>::N;
        let (mut wide, mut halves, mut narrow) = (vec![0.0; 16], vec![0.0; 16], vec![0.0; 16]);
        for o in (0..16).step_by(n) {
            let (a, b) = (w.load(&self.0[o..]), w.load(&self.1[o..]));
            let r = (a * b + a - b).fma(a, b).neg_fma(b, a);
            w.store(r, &mut wide[o..]);
            for h in 0..n / LANES {
                s.half(r, h).store(&mut halves[o + h * LANES..]);
            }
        }
        for o in (0..16).step_by(LANES) {
            let (a, b) = (s.load(&self.0[o..]), s.load(&self.1[o..]));
            let r = (a * b + a - b).mul_add(a, b).neg_mul_add(b, a);
            r.store(&mut narrow[o..]);
        }
        (n, wide, halves, narrow)
    }
}

#[test]
fn wide_vectors_compute_the_eight_lane_values_in_lane_order() {
    // Distinct lanes, so a swapped or repeated half shows; values whose products round.
    let a: Vec<f32> = (0..16).map(|i| 1.0 + i as f32 / 3.0).collect();
    let b: Vec<f32> = (0..16).map(|i| 0.7 - i as f32 / 7.0).collect();
    let want: Vec<f32> = (0..16)
        .map(|i| {
            let r = (a[i] * b[i] + a[i] - b[i]).mul_add(a[i], b[i]);
            (-r).mul_add(b[i], a[i])
        })
        .collect();
    let mut widths = Vec::new();
    for path in paths_run_by("wide_vectors_compute_the_eight_lane_values_in_lane_order") {
        let (n, wide, halves, narrow) = Dispatch::choose(path)
            .unwrap()
            .run(WideProbe(a.clone(), b.clone()));
        assert_eq!(wide, want, "{}: wide", path.name());
        assert_eq!(halves, want, "{}: halves", path.name());
        assert_eq!(narrow, want, "{}: eight lanes", path.name());
        widths.push((path, n));
    }
    for (path, n) in widths {
        let expected = if path == KernelPath::Avx512 { 16 } else { 8 };
        assert_eq!(n, expected, "{}", path.name());
    }
}

/// Two groups of eight loaded from anywhere ([`Width::load_groups`]), masked by sign and
/// compressed ([`Width::gt_mask`], [`Width::compress_store`]) at the path's widest width.
struct WideCompress(Vec<f32>, [usize; 2]);
impl Kernel for WideCompress {
    type Out = Vec<f32>;
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Vec<f32> {
        let w = s.wide();
        let n = <S::Wide as Width>::N;
        let mut out = vec![f32::NAN; 40];
        let mut at = 3;
        for h in 0..2 / (n / LANES) {
            // Eight lanes: one group per pass, as the gather's remainder loop.
            let groups = [self.1[h], self.1[h]];
            let v = w.load_groups(&self.0, if n == LANES { groups } else { self.1 });
            at += w.compress_store(v, w.gt_mask(v, w.zero()), &mut out, at);
        }
        out.truncate(at);
        out
    }
}

#[test]
fn wide_groups_load_mask_and_compress_in_lane_order() {
    // Signs vary per lane, NaN is never kept, and the second group comes before the first
    // in memory (as two culled chunks may).
    let v: Vec<f32> = (0..32)
        .map(|i| match i % 5 {
            0 => f32::NAN,
            1 | 3 => -(i as f32),
            _ => i as f32 + 0.5,
        })
        .collect();
    let at = [20, 4];
    let want: Vec<f32> = [at[0]..at[0] + 8, at[1]..at[1] + 8]
        .into_iter()
        .flatten()
        .map(|i| v[i])
        .filter(|x| *x > 0.0)
        .collect();
    assert!(want.len() > 4);
    for path in paths_run_by("wide_groups_load_mask_and_compress_in_lane_order") {
        let got = Dispatch::choose(path)
            .unwrap()
            .run(WideCompress(v.clone(), at));
        assert!(
            got[..3].iter().all(|x| x.is_nan()),
            "{}: wrote before `at`",
            path.name()
        );
        assert_eq!(got[3..], want[..], "{}", path.name());
    }
}

struct Transpose(Vec<f32>);
impl Kernel for Transpose {
    type Out = Vec<f32>;
    fn run<S: Isa>(self, s: S) -> Vec<f32> {
        let rows = std::array::from_fn(|i| s.load(&self.0[8 * i..]));
        let mut out = vec![0.0; 64];
        for (i, v) in s.transpose8(rows).into_iter().enumerate() {
            v.store(&mut out[8 * i..]);
        }
        out
    }
}

#[test]
fn transpose8_moves_every_lane_on_every_path() {
    // Distinct values, a NaN payload and a negative zero: moved, never computed.
    let mut m: Vec<f32> = (0..64).map(|k| k as f32 * 1.25 - 7.0).collect();
    m[9] = f32::from_bits(0x7fc0_1234);
    m[50] = -0.0;
    for path in paths_run_by("transpose8_moves_every_lane_on_every_path") {
        let got = Dispatch::choose(path).unwrap().run(Transpose(m.clone()));
        for i in 0..8 {
            for j in 0..8 {
                assert_eq!(
                    got[8 * i + j].to_bits(),
                    m[8 * j + i].to_bits(),
                    "{} ({i}, {j})",
                    path.name()
                );
            }
        }
    }
}

struct IntLanes(Vec<i32>, Vec<i32>, i32);
impl Kernel for IntLanes {
    type Out = (u32, u32, u32);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> (u32, u32, u32) {
        let (a, b, c) = (
            s.load_i32(&self.0),
            s.load_i32(&self.1),
            s.splat_i32(self.2),
        );
        (
            a.sign_mask(),
            a.add(b).sign_mask(),
            a.add(c).or(b).sign_mask(),
        )
    }
}

#[test]
fn i32_lanes_add_or_and_sign_on_every_path() {
    // Lane 7 wraps: i32::MAX + 1 is negative; lane 4 too: i32::MIN - 3 is positive (two's
    // complement, as documented).
    let a = vec![-1, 0, 5, -7, i32::MIN, 3, -2, i32::MAX];
    let b = vec![1, -1, -6, 7, 0, -4, 2, 1];
    let want = (0b0101_1001, 0b1011_0110, 0b0110_1111);
    for path in paths_run_by("i32_lanes_add_or_and_sign_on_every_path") {
        let got = Dispatch::choose(path)
            .unwrap()
            .run(IntLanes(a.clone(), b.clone(), -3));
        assert_eq!(got, want, "{}", path.name());
    }
}

struct F64Lanes(Vec<f64>, Vec<f64>, Vec<i32>);
impl Kernel for F64Lanes {
    type Out = (Vec<f64>, u32, Vec<f32>, f64);
    #[inline(always)]
    fn run<S: Isa>(self, s: S) -> Self::Out {
        let (a, b) = (s.load_f64(&self.0), s.load_f64(&self.1));
        let c = s.splat_f64(0.25);
        // Unfused on purpose: lane i must have the bits of scalar `a * b - 1`.
        let fma_like = a * b + s.splat_f64(-1.0);
        let quotient = (a - b) / (b * b + c);
        let root = (a * a + c).sqrt();
        let picked = a.select_gt(b, a.min(b), a.max(b));
        let mut out = vec![0.0; 16];
        for (k, v) in [fma_like, quotient, root, picked].into_iter().enumerate() {
            v.store(&mut out[4 * k..]);
        }
        let i = s.load_i32(&self.2);
        let narrowed = s.f64_to_f32(s.i32_to_f64(i, 0) * c, s.i32_to_f64(i, 1) / a);
        let mut f = vec![0.0f32; 8];
        narrowed.store(&mut f);
        (out, a.gt_mask(b), f, root.sum() + quotient.lane(3))
    }
}

#[test]
fn f64_lanes_give_the_bits_of_scalar_f64_on_every_path() {
    // Lane 0 and 3 hold a NaN and two zeros of opposite sign: min and max return the
    // second operand there (the documented rule); in lane 1, (1 + 3 eps)(1 - eps) - 1 is
    // 2 eps with the product rounded first and 2 eps - 3 eps^2 fused.
    let a = vec![f64::NAN, 1.0 + 3.0 * f64::EPSILON, -2.5, -0.0];
    let b = vec![1.0, 1.0 - f64::EPSILON, 7.0, 0.0];
    let ints = vec![-3, i32::MAX, 16_777_217, i32::MIN, 5, -7, 16_777_217, 1];
    let scalar_min = |x: f64, y: f64| if x < y { x } else { y };
    let scalar_max = |x: f64, y: f64| if x > y { x } else { y };
    let mut want = vec![0.0; 16];
    for i in 0..4 {
        let (x, y) = (a[i], b[i]);
        want[i] = x * y - 1.0;
        want[4 + i] = (x - y) / (y * y + 0.25);
        want[8 + i] = (x * x + 0.25).sqrt();
        want[12 + i] = if x > y {
            scalar_min(x, y)
        } else {
            scalar_max(x, y)
        };
    }
    let want_f32: Vec<f32> = (0..8)
        .map(|i| {
            if i < 4 {
                (ints[i] as f64 * 0.25) as f32
            } else {
                (ints[i] as f64 / a[i - 4]) as f32
            }
        })
        .collect();
    let want_sum = (want[8] + want[9]) + (want[10] + want[11]) + want[7];
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    for path in paths_run_by("f64_lanes_give_the_bits_of_scalar_f64_on_every_path") {
        let (got, mask, f, sum) =
            Dispatch::choose(path)
                .unwrap()
                .run(F64Lanes(a.clone(), b.clone(), ints.clone()));
        assert_eq!(bits(&got), bits(&want), "{}", path.name());
        assert_eq!(mask, 0b0010, "{}", path.name());
        let fb = |v: &[f32]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(fb(&f), fb(&want_f32), "{}", path.name());
        assert_eq!(sum.to_bits(), want_sum.to_bits(), "{}", path.name());
    }
    // The case the unfused rule is about: with a fused multiply-add, lane 1 differs.
    assert_ne!(
        a[1].mul_add(b[1], -1.0).to_bits(),
        want[1].to_bits(),
        "the test's product must need its own rounding"
    );
}
