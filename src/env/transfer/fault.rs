//! The faults a test can seed into the transfer table's build ([`super::build`] and the
//! FFT correlation of [`super::correlate`], which both apply them), in a file of their own
//! so that neither of the two imports the other for it.

/// **Test only**: faults seeded into the build, for the tests that show the accuracy
/// check fails on them.
#[doc(hidden)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum BuildFault {
    /// No fault: the shipped build.
    #[default]
    None,
    /// Nodes stored with the azimuth index slowest (`i * nv + j`) while the lookup reads
    /// `j * nu + i`: a transposed table axis.
    TransposedAxes,
    /// Texels below the node's horizon summed too: a missing hemisphere clip.
    NoHemisphereClip,
}
