//! **Test only**: faults seeded into the SH kernel path, for the mutation tests
//! (tests/integration/kernel_mutation.rs, tests/integration/sh_basis.rs).
//!
//! Design rule: the kernel itself stays as shipped. A fault is applied to the kernel's
//! inputs (per pixel, or per batch on the pixel-packed path) with exactly the effect a bug
//! in the kernel's loops or basis would have: a zero coefficient or a zero weight adds an
//! exact 0 to an FMA sum, which is what leaving the term or lane out of the loop gives. No
//! scene setting or command-line option reaches it: tests set it through
//! [`super::ShadeOptions`]' hidden `fault` field.

use crate::kernel::gather::Scratch;
use crate::lanes::LANES;
use crate::sh::dataset::ShDataset;
use glam::Vec3;

/// **Test only**: a fault seeded into the SH path (through [`super::ShadeOptions`]' hidden
/// `fault` field), each with exactly the effect a bug in the kernel's loops or basis would have.
/// Applied to the kernel's inputs per pixel (or per batch on the pixel-packed path), so the
/// kernel itself stays as shipped: a zero coefficient or a zero weight adds an exact 0 to an
/// FMA sum, which is what leaving the term or lane out of the loop gives.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KernelFault {
    /// The terms of the last SH band left out (a band loop one short).
    DropLastBand,
    /// Lane `.0` of every group of [`LANES`] left out: one light per group on the
    /// per-pixel path, one pixel per batch on the packed path (a wrong lane mask).
    DropLane(usize),
    /// The last group left out: the last (padded) group of lights on the per-pixel path,
    /// the last light on the packed path (a group loop one short).
    SkipLastGroup,
    /// The basis read from the data set's basis table
    /// ([`ShDataset::reconstruct_tabulated`]) instead of the analytic basis that defines it
    /// (what earlier versions did for point lights).
    TableBasis,
    /// The transfer term (`[env] method = "transfer"`) read one azimuth node over: the
    /// normal turned about +y by one node step before the table lookup (an off-by-one
    /// azimuth index in the fast path's lookup).
    TransferAzimuthShift,
}

/// Applies a seeded [`KernelFault`] to one pixel's kernel inputs (its coefficients `c`,
/// `[R.., G.., B..]`, and its light list `sc`); returns the pixel's result when the fault
/// replaces the kernel sum ([`KernelFault::TableBasis`]).
#[cold]
pub(super) fn seed_fault(
    fault: KernelFault,
    ds: &ShDataset,
    wo: Vec3,
    c: &mut [f32],
    sc: &mut Scratch,
) -> Option<Vec3> {
    match fault {
        KernelFault::DropLastBand => drop_last_band(c, ds.bands()),
        KernelFault::DropLane(lane) => {
            let end = sc.pad();
            for o in (0..end).step_by(LANES) {
                (sc.wr[o + lane], sc.wg[o + lane], sc.wb[o + lane]) = (0.0, 0.0, 0.0);
            }
        }
        KernelFault::SkipLastGroup => sc.n = (sc.n.div_ceil(LANES) - 1) * LANES,
        KernelFault::TransferAzimuthShift => {}
        KernelFault::TableBasis => {
            return Some((0..sc.n).fold(Vec3::ZERO, |sum, i| {
                let wi = Vec3::new(sc.x[i], sc.y[i], sc.z[i]);
                let w = Vec3::new(sc.wr[i], sc.wg[i], sc.wb[i]);
                sum + ds.reconstruct_tabulated(wi, wo) * w
            }));
        }
    }
    None
}

/// Zeroes the terms of band `bands - 1` in coefficients `[R.., G.., B..]` ([`KernelFault`]).
pub(super) fn drop_last_band(c: &mut [f32], bands: usize) {
    let t = bands * bands;
    for colour in c.chunks_exact_mut(t) {
        colour[(bands - 1) * (bands - 1)..].fill(0.0);
    }
}

/// `n` turned about +y by one azimuth node step of `table` ([`KernelFault`]).
#[cold]
pub(super) fn shift_one_azimuth_node(table: &crate::env::transfer::TransferTable, n: Vec3) -> Vec3 {
    let step = std::f32::consts::TAU / table.grid().0 as f32;
    glam::Quat::from_rotation_y(step) * n
}
