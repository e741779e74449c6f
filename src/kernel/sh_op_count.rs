//! Test only: the SH recurrence costs no more vector operations than the coefficient FMAs
//! it feeds. [`sh_dot`] runs here on a one-lane counting type, which
//! counts every arithmetic operation it is given (add, subtract, multiply, FMA); the
//! coefficient FMAs are exactly three per term (R, G, B), and everything else is the
//! associated-Legendre recurrence, the azimuth rotation and the basis scaling.

use super::{sh_dot, ShRecurrence};
use crate::lanes::{Arith, Width};
use std::cell::Cell;
use std::ops::{Add, AddAssign, Mul, Sub};

thread_local! {
    static OPS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    OPS.with(|c| c.set(c.get() + 1));
}

/// One lane that counts the operations done on it.
#[derive(Clone, Copy, Debug)]
struct Counted(f32);

impl Add for Counted {
    type Output = Counted;
    fn add(self, o: Counted) -> Counted {
        count();
        Counted(self.0 + o.0)
    }
}
impl Sub for Counted {
    type Output = Counted;
    fn sub(self, o: Counted) -> Counted {
        count();
        Counted(self.0 - o.0)
    }
}
impl Mul for Counted {
    type Output = Counted;
    fn mul(self, o: Counted) -> Counted {
        count();
        Counted(self.0 * o.0)
    }
}
impl AddAssign for Counted {
    fn add_assign(&mut self, o: Counted) {
        count();
        self.0 += o.0;
    }
}
impl Arith for Counted {
    fn fma(self, b: Counted, c: Counted) -> Counted {
        count();
        Counted(self.0.mul_add(b.0, c.0))
    }
    fn neg_fma(self, b: Counted, c: Counted) -> Counted {
        count();
        Counted((-self.0).mul_add(b.0, c.0))
    }
}

#[derive(Clone, Copy)]
struct OneLane;

impl Width for OneLane {
    type V = Counted;
    const N: usize = 1;
    fn splat(self, v: f32) -> Counted {
        Counted(v)
    }
    fn load(self, s: &[f32]) -> Counted {
        Counted(s[0])
    }
    fn store(self, v: Counted, out: &mut [f32]) {
        out[0] = v.0;
    }
    fn load_groups(self, s: &[f32], at: [usize; 2]) -> Counted {
        Counted(s[at[0]])
    }
    fn gt_mask(self, v: Counted, o: Counted) -> u32 {
        (v.0 > o.0) as u32
    }
    fn compress_store(self, v: Counted, mask: u32, out: &mut [f32], at: usize) -> usize {
        out[at] = v.0;
        (mask & 1) as usize
    }
}

/// Operations of one [`sh_dot`] call (one group of lights) at `bands` bands, per-pixel or
/// pixel-packed coefficients.
fn ops(bands: usize, packed: bool) -> usize {
    let rec = ShRecurrence::new(bands);
    let c = vec![0.5f32; 3 * bands * bands];
    OPS.with(|o| o.set(0));
    let w = OneLane;
    let (r, g, b) = sh_dot(
        w,
        bands,
        &rec,
        &c,
        packed,
        Counted(0.6),
        Counted(0.0),
        Counted(0.8),
    );
    assert!(r.0.is_finite() && g.0.is_finite() && b.0.is_finite());
    OPS.with(|o| o.get())
}

#[test]
fn the_recurrence_costs_no_more_operations_than_the_coefficient_fmas() {
    for bands in 1..=10 {
        for packed in [false, true] {
            let total = ops(bands, packed);
            let fmas = 3 * bands * bands;
            assert!(total >= fmas, "{bands} bands: {total} operations");
            let recurrence = total - fmas;
            println!(
                "{bands} bands: {fmas} coefficient FMAs, {recurrence} other operations \
                 ({:.2} per FMA)",
                recurrence as f64 / fmas as f64
            );
            assert!(
                recurrence <= fmas,
                "{bands} bands: the recurrence takes {recurrence} operations for {fmas} \
                 coefficient FMAs"
            );
        }
    }
}

/// The instrument: the counting lane counts each operation once, whatever its kind.
#[test]
fn the_counting_lane_counts_every_operation() {
    OPS.with(|o| o.set(0));
    let (a, b) = (Counted(2.0), Counted(3.0));
    let mut v = a.fma(b, a) + a * b - b.neg_fma(a, b);
    v += a;
    assert_eq!(v.0, 2.0 * 3.0 + 2.0 + 6.0 - (3.0 - 6.0) + 2.0);
    assert_eq!(OPS.with(|o| o.get()), 6);
}
