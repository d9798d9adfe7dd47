//! Geometry of the `N x N` dune torus: cells `y * N + x`, split into column and row start,
//! the 8 Moore neighbours in the engine's order, and downwind columns, all without division
//! on the hot paths.

/// `(x, row start)` of cell `c`: `x = c mod N`, `row = c - x` (32-bit division: the grid
/// has at most 4096^2 cells).
#[inline(always)]
pub(super) fn split(n: usize, c: usize) -> (usize, usize) {
    let x = (c as u32 % n as u32) as usize;
    (x, c - x)
}

/// The 8 neighbours of the cell in column `x` of the row starting at `row`, in the order of
/// the engine's [`MOORE`](crate::engine::lattice::MOORE) offsets (edge neighbours at even
/// positions, diagonal ones at odd), as `(cell, column, row start)`; no division.
#[inline(always)]
pub(super) fn moore(n: usize, x: usize, row: usize) -> [(usize, usize, usize); 8] {
    let cells = n * n;
    let xm = if x == 0 { n - 1 } else { x - 1 };
    let xp = if x + 1 == n { 0 } else { x + 1 };
    let rm = if row == 0 { cells - n } else { row - n };
    let rp = if row + n == cells { 0 } else { row + n };
    [
        (row + xp, xp, row),
        (rp + xp, xp, rp),
        (rp + x, x, rp),
        (rp + xm, xm, rp),
        (row + xm, xm, row),
        (rm + xm, xm, rm),
        (rm + x, x, rm),
        (rm + xp, xp, rm),
    ]
}

/// Column `jump` cells downwind of column `x` (wrapping, any `jump`).
#[inline(always)]
pub(super) fn downwind_x(n: usize, x: usize, jump: i64) -> usize {
    // Jumps are mostly shorter than the grid: no division then.
    let j = if (0..n as i64).contains(&jump) {
        jump as usize
    } else {
        jump.rem_euclid(n as i64) as usize
    };
    let mut nx = x + j;
    if nx >= n {
        nx -= n;
    }
    nx
}
