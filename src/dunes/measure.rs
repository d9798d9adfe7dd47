//! Observables of a dune field: dune bodies (connected components above a threshold), bare
//! fraction, height range and the sand balance.

use petgraph::unionfind::UnionFind;
use serde::Serialize;

use super::{GRAINS_PER_UNIT, to_units};
use crate::engine::lattice::{Edge, Lattice};

/// Connected components of a set of cells (see [`bodies`]).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Bodies {
    /// Number of components.
    pub count: usize,
    /// Cells per component, by label.
    pub sizes: Vec<usize>,
    /// Label `0..count` of each cell's component, or `u32::MAX` for a cell not in the set.
    /// Labels follow the first cell of each component in index order.
    pub labels: Vec<u32>,
    /// Per component: whether it wraps round the torus along `x` (a closed path through it
    /// goes once or more round the grid downwind).
    pub wraps_x: Vec<bool>,
    /// Per component: whether it wraps round the torus along `y` (across the wind: a
    /// transverse ridge that spans the grid).
    pub wraps_y: Vec<bool>,
}

impl Bodies {
    /// Cells of the largest component (0 when there is none).
    pub fn largest(&self) -> usize {
        self.sizes.iter().copied().max().unwrap_or(0)
    }

    /// Components that wrap round the torus along `x` or `y` (span the grid).
    pub fn spanning(&self) -> usize {
        self.wraps_x
            .iter()
            .zip(&self.wraps_y)
            .filter(|(a, b)| **a || **b)
            .count()
    }
}

/// Connected components of the cells with `inside[c]`, neighbours as in `lattice` (for
/// dunes the 8-neighbour torus, so a body wrapping round the grid is one body), found with
/// petgraph's union-find; then, per component, whether it wraps round a periodic axis
/// (a walk over the component with unwrapped coordinates reaches some cell at two positions
/// a period apart).
///
/// # Panics
///
/// If `inside.len()` is not the lattice's cell count.
pub fn bodies(inside: &[bool], lattice: &Lattice) -> Bodies {
    let cells = lattice.len();
    assert_eq!(inside.len(), cells, "bodies: one flag per cell");
    let mut uf: UnionFind<u32> = UnionFind::new(cells);
    for c in 0..cells {
        if !inside[c] {
            continue;
        }
        for &nb in lattice.neighbour_list(c).as_slice() {
            if inside[nb as usize] {
                uf.union(c as u32, nb);
            }
        }
    }
    let mut root_label = vec![u32::MAX; cells];
    let mut labels = vec![u32::MAX; cells];
    let mut sizes = Vec::new();
    for c in 0..cells {
        if !inside[c] {
            continue;
        }
        let r = uf.find_mut(c as u32) as usize;
        if root_label[r] == u32::MAX {
            root_label[r] = sizes.len() as u32;
            sizes.push(0);
        }
        let l = root_label[r];
        labels[c] = l;
        sizes[l as usize] += 1;
    }
    let (wraps_x, wraps_y) = windings(&labels, sizes.len(), lattice);
    Bodies {
        count: sizes.len(),
        sizes,
        labels,
        wraps_x,
        wraps_y,
    }
}

/// Whether each component wraps round the lattice along `x` and along `y`: a walk from the
/// component's first cell gives every cell unwrapped coordinates; an edge that closes at a
/// position a period away from the one recorded closes a loop round the torus.
fn windings(labels: &[u32], count: usize, lattice: &Lattice) -> (Vec<bool>, Vec<bool>) {
    let (w, h) = (lattice.width() as i64, lattice.height() as i64);
    let wall_x = lattice.boundary().x == Edge::Wall;
    let wall_y = lattice.boundary().y == Edge::Wall;
    let mut wx = vec![false; count];
    let mut wy = vec![false; count];
    let mut pos: Vec<(i64, i64)> = vec![(i64::MIN, 0); labels.len()];
    let mut stack: Vec<usize> = Vec::new();
    for start in 0..labels.len() {
        if labels[start] == u32::MAX || pos[start].0 != i64::MIN {
            continue;
        }
        let l = labels[start] as usize;
        let (x0, y0) = lattice.coords(start);
        pos[start] = (x0 as i64, y0 as i64);
        stack.push(start);
        while let Some(c) = stack.pop() {
            let (ux, uy) = pos[c];
            let y = uy.rem_euclid(h) as usize;
            for &(dx, dy) in lattice.neighbourhood().offsets(y) {
                let (nx, ny) = (ux + i64::from(dx), uy + i64::from(dy));
                // Beyond a wall there is no neighbour (unwrapped positions stay in range).
                if (wall_x && !(0..w).contains(&nx)) || (wall_y && !(0..h).contains(&ny)) {
                    continue;
                }
                let nb = lattice.index(nx.rem_euclid(w) as usize, ny.rem_euclid(h) as usize);
                if labels[nb] != labels[c] {
                    continue;
                }
                if pos[nb].0 == i64::MIN {
                    pos[nb] = (nx, ny);
                    stack.push(nb);
                } else {
                    wx[l] |= pos[nb].0 != nx;
                    wy[l] |= pos[nb].1 != ny;
                }
            }
        }
    }
    (wx, wy)
}

/// The observables of a dune field.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct DuneStats {
    /// Iterations done.
    pub iteration: u64,
    /// Mean height, height units (total sand / `N^2`).
    pub mean_height: f64,
    /// Lowest cell, height units (never negative).
    pub min_height: f64,
    /// Highest cell, height units.
    pub max_height: f64,
    /// Body threshold, height units (default [`BODY_THRESHOLD`](super::BODY_THRESHOLD)).
    pub threshold: f64,
    /// Separate dune bodies: connected components (8 neighbours, torus) of the cells above
    /// the threshold.
    pub dune_bodies: usize,
    /// Bodies that wrap round the torus (span the grid): transverse ridges do, barchans do
    /// not.
    pub spanning_bodies: usize,
    /// Fraction of cells at or below the threshold (bare ground).
    pub bare_fraction: f64,
    /// Cells of the largest body over `N^2`.
    pub largest_body_fraction: f64,
    /// Total sand, grains.
    pub total_grains: u64,
    /// Total sand now minus at the start, grains: 0 (sand is conserved exactly).
    pub sand_change: i64,
}

/// The cells of `h` (grains) higher than `threshold` height units.
pub fn above_threshold(h: &[u64], threshold: f64) -> Vec<bool> {
    let t = threshold * GRAINS_PER_UNIT as f64;
    h.iter().map(|&v| v as f64 > t).collect()
}

/// The observables of the heights `h` (grains) on `lattice` after `iteration` iterations, with
/// `sand_change` grains gained since the start and bodies made of the cells higher than
/// `threshold` height units.
pub(super) fn stats(
    h: &[u64],
    lattice: &Lattice,
    iteration: u64,
    sand_change: i128,
    threshold: f64,
) -> DuneStats {
    let cells = h.len();
    let inside = above_threshold(h, threshold);
    let b = bodies(&inside, lattice);
    let bare = inside.iter().filter(|&&i| !i).count();
    let total: u64 = h.iter().sum();
    DuneStats {
        iteration,
        mean_height: to_units(total) / cells as f64,
        min_height: to_units(h.iter().copied().min().unwrap_or(0)),
        max_height: to_units(h.iter().copied().max().unwrap_or(0)),
        threshold,
        dune_bodies: b.count,
        spanning_bodies: b.spanning(),
        bare_fraction: bare as f64 / cells as f64,
        largest_body_fraction: b.largest() as f64 / cells as f64,
        total_grains: total,
        sand_change: sand_change as i64,
    }
}
