//! Tests of the lane wrapper: every dispatch path computes the same lanes.

use super::*;

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
    let got = Dispatch::detect().run(Probe(a.clone(), b.clone()));
    assert_eq!(want, got);
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
    for path in KernelPath::available() {
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
