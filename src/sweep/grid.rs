//! The grid of a sweep: its axes ([`Grid`]), one point of it ([`Config`]), the scene's own
//! point ([`DefaultConfig`]), and the names the CLI, the CSV and the plot give axis values.
//!
//! Design rule: the enumeration order is fixed (sampler outermost, then light count, SH
//! order, lookup, precision innermost) and a [`Config::index`] is the position in the
//! *whole* grid, so shards ([`crate::shard`]) and merged CSVs agree on it. An axis value has
//! one name everywhere: [`sampler_name`], [`lookup_name`] and [`precision_name`] write it,
//! [`parse_sampler`] and [`parse_lookup`] read it back.

use crate::env::prepare::SamplerKind;
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
    pub samplers: Vec<SamplerKind>,
    /// Requested light counts (the sampler's `n`).
    pub counts: Vec<usize>,
    /// SH orders (bands kept, `l < order`); `[0]` for a material that is not SH.
    pub orders: Vec<usize>,
    /// Coefficient-table lookups; `[None]` for a material that is not SH.
    pub lookups: Vec<Option<Lookup>>,
    pub precisions: Vec<Precision>,
}

impl Default for Grid {
    fn default() -> Self {
        Grid {
            samplers: default_samplers(),
            counts: default_counts(),
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
    pub sampler: SamplerKind,
    pub lights: usize,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl Grid {
    /// Number of configurations.
    pub fn len(&self) -> usize {
        self.samplers.len()
            * self.counts.len()
            * self.orders.len()
            * self.lookups.len()
            * self.precisions.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Every configuration, in index order.
    pub fn configs(&self) -> Vec<Config> {
        let mut out = Vec::with_capacity(self.len());
        for &sampler in &self.samplers {
            for &lights in &self.counts {
                for &order in &self.orders {
                    for &lookup in &self.lookups {
                        for &precision in &self.precisions {
                            out.push(Config {
                                index: out.len(),
                                sampler,
                                lights,
                                order,
                                lookup,
                                precision,
                            });
                        }
                    }
                }
            }
        }
        out
    }

    /// Fits the SH axes to the scene's material: orders above `bands` are dropped (an error
    /// if none remain); a material that is not SH (`bands == None`) gets `[0]` and `[None]`.
    pub fn fit_material(&mut self, bands: Option<usize>) -> Result<()> {
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
        Ok(())
    }
}

/// The scene's own configuration, to mark the default row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DefaultConfig {
    pub sampler: SamplerKind,
    pub lights: usize,
    pub order: usize,
    pub lookup: Option<Lookup>,
    pub precision: Precision,
}

impl DefaultConfig {
    /// Whether `c` is this configuration.
    pub fn matches(&self, c: &Config) -> bool {
        c.sampler == self.sampler
            && c.lights == self.lights
            && c.order == self.order
            && c.lookup == self.lookup
            && c.precision == self.precision
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_order_and_size() {
        let g = Grid::default();
        assert_eq!(g.len(), 880);
        let c = g.configs();
        assert_eq!(c.len(), 880);
        assert!(c.iter().enumerate().all(|(i, c)| c.index == i));
        // precision innermost, then lookup, order, count; sampler outermost
        assert_eq!(c[1].lookup, Some(Lookup::Bilinear));
        assert_eq!(c[2].order, 2);
        assert_eq!(c[16].lights, 2);
        assert_eq!(c[176].sampler, SamplerKind::Importance);
    }

    #[test]
    fn fit_material_drops_orders() {
        let mut g = Grid::default();
        g.fit_material(Some(5)).unwrap();
        assert_eq!(g.orders, vec![1, 2, 3, 4, 5]);
        let mut g = Grid::default();
        g.fit_material(None).unwrap();
        assert_eq!((g.orders.clone(), g.lookups.clone()), (vec![0], vec![None]));
        let mut g = Grid {
            orders: vec![9],
            ..Grid::default()
        };
        assert!(g.fit_material(Some(8)).is_err());
    }
}
