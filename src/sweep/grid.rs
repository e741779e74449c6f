//! The grid of a sweep: its axes ([`Grid`]), one point of it ([`Config`]), the scene's own
//! point ([`DefaultConfig`]), and the names the CLI, the CSV and the plot give axis values.
//!
//! (Past 400 lines because it is one concept, the grid and its enumeration order; the axes'
//! names, their parsers and the enumeration must change together, and the design rule below
//! depends on that.)
//!
//! Design rule: the enumeration order is fixed (the environment method outermost with its
//! own parameters, then SH order, lookup, precision innermost) and a [`Config::index`] is
//! the position in the *whole* grid, so shards ([`crate::shard`]) and merged CSVs agree on
//! it. An axis value has one name everywhere: [`sampler_name`], [`lookup_name`],
//! [`precision_name`] and [`MethodKind::name`] write it, [`parse_sampler`],
//! [`parse_lookup`] and [`MethodKind::parse`] read it back.
//!
//! # The method axis
//! [`MethodKind`] is a method of `[env] method` ([`EnvMethod`]) the sweep can run,
//! [`MethodAxis`] one value of the axis: a method with its parameters. `lights` comes
//! first (sampler x light count, as before methods were swept, so a lights-only grid has
//! the same row indices as then), then `transfer` (table grid `azimuth x polar` pairs x
//! `exact_lights`), then `lightcuts` (`cut_error` x `cut_max`), then `reflection`
//! (`reflection_grid` x `exact_lights`; the other bake parameters at the scene's values).
//!
//! Adding a method: a variant in [`MethodKind`] and in [`MethodAxis`] with its parameters,
//! its parameter lists in [`Grid`], and then the arms the compiler asks for (every `match`
//! here and in `csv.rs`, `run.rs` and `plot.rs` is exhaustive): the enumeration in
//! [`Grid::method_points`], [`MethodAxis::of_spec`], the CSV's parameter columns (a new
//! column changes the CSV format) and the runner's preparation of the method's scene. An
//! `[env]` method without a [`MethodKind`] is not swept ([`MethodKind::of`] is `None`) and
//! needs nothing here.

use crate::env::schema::{EnvMethod, EnvSpec, SamplerKind};
use crate::error::{Error, Result};
use crate::scene::Precision;
use crate::sh::dataset::Lookup;

/// Default light counts: 1, 2, 4, ..., 1024.
pub fn default_counts() -> Vec<usize> {
    (0..=10).map(|k| 1usize << k).collect()
}

/// The samplers a sweep runs by default: every [`SamplerKind`] except `full` (the reference).
pub fn default_samplers() -> Vec<SamplerKind> {
    vec![
        SamplerKind::Uniform,
        SamplerKind::Importance,
        SamplerKind::Stratified,
        SamplerKind::MedianCut,
        SamplerKind::Lloyd,
    ]
}

/// Default transfer-table grids `(azimuth, polar)` nodes: 32 x 17, 64 x 33 and 128 x 65
/// (the last one the `[env]` default; each divides the shipped probes' 512 columns).
pub fn default_transfer_grids() -> Vec<(usize, usize)> {
    vec![(32, 17), (64, 33), (128, 65)]
}

/// Default numbers of brightest texels summed exactly beside a transfer table: 0, 16 and
/// 64 (the `[env]` default, [`DEFAULT_EXACT_LIGHTS`](crate::env::schema::DEFAULT_EXACT_LIGHTS)).
pub fn default_exact_lights() -> Vec<usize> {
    vec![0, 16, 64]
}

/// Default reflection-table grids (`[env] reflection_grid`, cells per side of the octahedral
/// grid of reflected directions): 32 and 64 (the `[env]` default).
pub fn default_reflection_grids() -> Vec<usize> {
    vec![32, 64]
}

/// Default light-cut error bounds (`[env] cut_error`): 0.005, 0.01 (the `[env]` default),
/// 0.02 and 0.05.
pub fn default_cut_errors() -> Vec<f32> {
    vec![0.005, 0.01, 0.02, 0.05]
}

/// Default largest cuts (`[env] cut_max`): the `[env]` default only.
pub fn default_cut_maxes() -> Vec<usize> {
    vec![crate::env::schema::DEFAULT_CUT_MAX]
}

/// The environment methods a sweep runs (the outer axis), a subset of `[env] method`
/// ([`EnvMethod`]) under the same names.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum MethodKind {
    /// Delta lights from a sampler (`[env] method = "lights"`): sampler x count.
    Lights,
    /// Transfer table plus the brightest texels (`[env] method = "transfer"`): table grid
    /// x exact lights. SH data sets and Lambert only.
    Transfer,
    /// Adaptive light cuts through a tree of every texel (`[env] method = "lightcuts"`):
    /// cut error x largest cut. Every material with a cone bound (not SH, not MERL).
    Lightcuts,
    /// Reflection-space radiance table plus the brightest texels (`[env] method =
    /// "reflection"`): table grid x exact lights. Isotropic materials that are not SH data
    /// sets (an SH set's bake evaluates the set per sample: minutes; its method is the
    /// transfer table).
    Reflection,
}

impl MethodKind {
    /// Every method, in the grid's order.
    pub const ALL: [MethodKind; 4] = [
        MethodKind::Lights,
        MethodKind::Transfer,
        MethodKind::Lightcuts,
        MethodKind::Reflection,
    ];

    /// The `[env] method` this is.
    pub fn env_method(self) -> EnvMethod {
        match self {
            MethodKind::Lights => EnvMethod::Lights,
            MethodKind::Transfer => EnvMethod::Transfer,
            MethodKind::Lightcuts => EnvMethod::Lightcuts,
            MethodKind::Reflection => EnvMethod::Reflection,
        }
    }

    /// The sweep's method that is `method`, `None` for a method the sweep does not run
    /// (`auto`): the inverse of [`MethodKind::env_method`], so a new `[env]`
    /// method is swept only once a variant here names it.
    pub fn of(method: EnvMethod) -> Option<MethodKind> {
        MethodKind::ALL
            .into_iter()
            .find(|m| m.env_method() == method)
    }

    /// The name, as `[env] method` and `--method` spell it (`lights`, `transfer`).
    pub fn name(self) -> String {
        use clap::ValueEnum;
        self.env_method()
            .to_possible_value()
            .map(|v| v.get_name().to_string())
            .unwrap_or_default()
    }

    /// Parses [`MethodKind::name`]'s output.
    pub fn parse(s: &str) -> Option<MethodKind> {
        MethodKind::ALL.into_iter().find(|m| m.name() == s)
    }
}

/// One value of the method axis: an environment method with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MethodAxis {
    /// `count` delta lights from `sampler` (`[env] sampler`, `count`).
    Lights { sampler: SamplerKind, count: usize },
    /// A transfer table of `azimuth x polar` nodes (`[env] transfer_azimuth`,
    /// `transfer_polar`) and the `exact_lights` brightest texels as lights.
    Transfer {
        azimuth: usize,
        polar: usize,
        exact_lights: usize,
    },
    /// Light cuts refined to `cut_error` of the pixel, at most `cut_max` clusters
    /// (`[env] cut_error`, `cut_max`).
    Lightcuts { cut_error: f32, cut_max: usize },
    /// A reflection table of `grid x grid` cells (`[env] reflection_grid`) and the
    /// `exact_lights` brightest texels as lights.
    Reflection { grid: usize, exact_lights: usize },
}

impl MethodAxis {
    /// The method.
    pub fn kind(&self) -> MethodKind {
        match self {
            MethodAxis::Lights { .. } => MethodKind::Lights,
            MethodAxis::Transfer { .. } => MethodKind::Transfer,
            MethodAxis::Lightcuts { .. } => MethodKind::Lightcuts,
            MethodAxis::Reflection { .. } => MethodKind::Reflection,
        }
    }

    /// What a scene's `[env]` asks for (its own point of the axis); `None` for a method the
    /// sweep does not run (no [`MethodKind`] is it, [`MethodKind::of`]; `auto` is made
    /// concrete first).
    pub fn of_spec(spec: &EnvSpec) -> Option<MethodAxis> {
        Some(match MethodKind::of(spec.method)? {
            MethodKind::Lights => MethodAxis::Lights {
                sampler: spec.sampler,
                count: spec.count,
            },
            MethodKind::Transfer => MethodAxis::Transfer {
                azimuth: spec.transfer_azimuth,
                polar: spec.transfer_polar,
                exact_lights: spec.exact_lights,
            },
            MethodKind::Lightcuts => MethodAxis::Lightcuts {
                cut_error: spec.cut_error,
                cut_max: spec.cut_max,
            },
            MethodKind::Reflection => MethodAxis::Reflection {
                grid: spec.reflection_grid,
                exact_lights: spec.exact_lights,
            },
        })
    }

    /// A short label: `lloyd 128`, `transfer 128x65 k16`.
    pub fn label(&self) -> String {
        match *self {
            MethodAxis::Lights { sampler, count } => format!("{} {count}", sampler_name(sampler)),
            MethodAxis::Transfer {
                azimuth,
                polar,
                exact_lights,
            } => format!("transfer {azimuth}x{polar} k{exact_lights}"),
            MethodAxis::Lightcuts { cut_error, cut_max } => {
                format!("lightcuts e{cut_error} m{cut_max}")
            }
            MethodAxis::Reflection { grid, exact_lights } => {
                format!("reflection {grid} k{exact_lights}")
            }
        }
    }
}

/// A configuration in words: `lights lloyd 128, order 8, bilinear, f32`,
/// `transfer 128x65 exact 16, order 8, bilinear, f32` (order and lookup left out for a
/// material that is not SH).
pub fn describe(c: &Config) -> String {
    let method = match c.method {
        MethodAxis::Lights { sampler, count } => {
            format!("lights {} {count}", sampler_name(sampler))
        }
        MethodAxis::Transfer {
            azimuth,
            polar,
            exact_lights,
        } => format!("transfer {azimuth}x{polar} exact {exact_lights}"),
        MethodAxis::Lightcuts { cut_error, cut_max } => {
            format!("lightcuts error {cut_error} max {cut_max}")
        }
        MethodAxis::Reflection { grid, exact_lights } => {
            format!("reflection {grid}x{grid} exact {exact_lights}")
        }
    };
    let sh = match c.lookup {
        Some(l) => format!(", order {}, {}", c.order, lookup_name(Some(l))),
        None => String::new(),
    };
    format!("{method}{sh}, {}", precision_name(c.precision))
}

/// The sampler's command-line name (`median-cut`, ...).
pub fn sampler_name(s: SamplerKind) -> String {
    use clap::ValueEnum;
    s.to_possible_value()
        .map(|v| v.get_name().to_string())
        .unwrap_or_default()
}

/// Parses a sampler name as [`sampler_name`] writes it.
pub fn parse_sampler(s: &str) -> Option<SamplerKind> {
    use clap::ValueEnum;
    SamplerKind::from_str(s, false).ok()
}

/// `nearest` / `bilinear`, `-` for none.
pub fn lookup_name(l: Option<Lookup>) -> &'static str {
    match l {
        Some(Lookup::Nearest) => "nearest",
        Some(Lookup::Bilinear) => "bilinear",
        None => "-",
    }
}

/// Parses [`lookup_name`]'s output (`-` is `Some(None)`).
pub fn parse_lookup(s: &str) -> Option<Option<Lookup>> {
    match s {
        "nearest" => Some(Some(Lookup::Nearest)),
        "bilinear" => Some(Some(Lookup::Bilinear)),
        "-" => Some(None),
        _ => None,
    }
}

/// `f32` / `f64`.
pub fn precision_name(p: Precision) -> &'static str {
    match p {
        Precision::F32 => "f32",
        Precision::F64 => "f64",
    }
}

/// The axes of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// The methods, outermost axis, in this order.
    pub methods: Vec<MethodKind>,
    /// `lights`: samplers.
    pub samplers: Vec<SamplerKind>,
    /// `lights`: requested light counts (the sampler's `n`).
    pub counts: Vec<usize>,
    /// `transfer`: table grids, `(azimuth, polar)` nodes.
    pub transfer_grids: Vec<(usize, usize)>,
    /// `transfer` and `reflection`: brightest texels summed exactly.
    pub exact_lights: Vec<usize>,
    /// `lightcuts`: cut error bounds (relative to the pixel).
    pub cut_errors: Vec<f32>,
    /// `lightcuts`: largest cuts.
    pub cut_maxes: Vec<usize>,
    /// `reflection`: table grids (cells per side).
    pub reflection_grids: Vec<usize>,
    /// SH orders (bands kept, `l < order`); `[0]` for a material that is not SH.
    pub orders: Vec<usize>,
    /// Coefficient-table lookups; `[None]` for a material that is not SH.
    pub lookups: Vec<Option<Lookup>>,
    pub precisions: Vec<Precision>,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            methods: MethodKind::ALL.to_vec(),
            samplers: default_samplers(),
            counts: default_counts(),
            transfer_grids: default_transfer_grids(),
            exact_lights: default_exact_lights(),
            cut_errors: default_cut_errors(),
            cut_maxes: default_cut_maxes(),
            reflection_grids: default_reflection_grids(),
            orders: (1..=8).collect(),
            lookups: vec![Some(Lookup::Nearest), Some(Lookup::Bilinear)],
            precisions: vec![Precision::F32],
        }
    }
}

/// One configuration of the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Config {
    /// Position in the whole grid (see the module doc).
    pub index: usize,
    /// The environment method and its parameters.
    pub method: MethodAxis,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl Grid {
    /// The values of the method axis, in order: each method of [`Grid::methods`] with the
    /// product of its parameter lists (first list outermost).
    pub fn method_points(&self) -> Vec<MethodAxis> {
        let mut out = Vec::new();
        for &m in &self.methods {
            match m {
                MethodKind::Lights => {
                    for &sampler in &self.samplers {
                        for &count in &self.counts {
                            out.push(MethodAxis::Lights { sampler, count });
                        }
                    }
                }
                MethodKind::Transfer => {
                    for &(azimuth, polar) in &self.transfer_grids {
                        for &exact_lights in &self.exact_lights {
                            out.push(MethodAxis::Transfer {
                                azimuth,
                                polar,
                                exact_lights,
                            });
                        }
                    }
                }
                MethodKind::Lightcuts => {
                    for &cut_error in &self.cut_errors {
                        for &cut_max in &self.cut_maxes {
                            out.push(MethodAxis::Lightcuts { cut_error, cut_max });
                        }
                    }
                }
                MethodKind::Reflection => {
                    for &grid in &self.reflection_grids {
                        for &exact_lights in &self.exact_lights {
                            out.push(MethodAxis::Reflection { grid, exact_lights });
                        }
                    }
                }
            }
        }
        out
    }

    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.method_points().len() * self.orders.len() * self.lookups.len() * self.precisions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every configuration, in index order.
    pub fn configs(&self) -> Vec<Config> {
        let mut out = Vec::with_capacity(self.len());
        for method in self.method_points() {
            for &order in &self.orders {
                for &lookup in &self.lookups {
                    for &precision in &self.precisions {
                        out.push(Config {
                            index: out.len(),
                            method,
                            order,
                            lookup,
                            precision,
                        });
                    }
                }
            }
        }
        out
    }

    /// Fits the grid to the scene's material. SH axes: orders above `bands` are dropped (an
    /// error if none remain); a material that is not SH (`bands == None`) gets `[0]` and
    /// `[None]`. Methods: each method `shades` refuses for the material (`Some(why)`:
    /// `transfer` shades SH data sets and Lambert only, `lightcuts` every material with a
    /// cone bound) is dropped with a note saying why; an error when no method remains.
    /// Returns a note per method dropped, for the command line to print.
    pub fn fit_material(
        &mut self,
        bands: Option<usize>,
        shades: impl Fn(MethodKind) -> Option<String>,
    ) -> Result<Vec<String>> {
        match bands {
            None => {
                self.orders = vec![0];
                self.lookups = vec![None];
            }
            Some(b) => {
                self.orders.retain(|&o| o >= 1 && o <= b);
                if self.orders.is_empty() {
                    return Err(Error::field(
                        "--orders",
                        format!("no order in 1..={b}: the material's data set stores {b} bands"),
                    ));
                }
                if self.lookups.iter().any(Option::is_none) {
                    return Err(Error::field("--lookups", "give nearest and/or bilinear"));
                }
            }
        }
        let mut notes = Vec::new();
        let mut why_none = Vec::new();
        self.methods.retain(|&m| match shades(m) {
            None => true,
            Some(why) => {
                notes.push(format!("method {} left out: {why}", m.name()));
                why_none.push(format!("{} {why}", m.name()));
                false
            }
        });
        if self.methods.is_empty() {
            return Err(Error::field(
                "--methods",
                format!("no method left: {}", why_none.join("; ")),
            ));
        }
        Ok(notes)
    }
}

/// The scene's own configuration, to mark the default row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefaultConfig {
    /// `None` when the scene's `[env] method` is not swept.
    pub method: Option<MethodAxis>,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl DefaultConfig {
    /// Whether `c` is this configuration.
    pub fn matches(&self, c: &Config) -> bool {
        self.method == Some(c.method)
            && c.order == self.order
            && c.lookup == self.lookup
            && c.precision == self.precision
    }
}

#[cfg(test)]
mod tests;
