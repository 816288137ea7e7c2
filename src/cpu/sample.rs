//! Bilinear sampling of cell-centred grids, zero outside. Twin of `shaders/shared/sample.wgsl`.

/// Bilinear interpolation of a `res × res` row-major grid at continuous index coordinates
/// (`x` = column, `y` = row; integers are cell centres). Cells outside the grid read as zero, so
/// the value fades to zero over the half cell past the border.
#[inline]
pub(crate) fn bilinear<T>(cells: &[T], res: u32, x: f32, y: f32) -> T
where
    T: Copy + Default + std::ops::Mul<f32, Output = T> + std::ops::Add<Output = T>,
{
    if !near_grid(res, x, y) {
        return T::default(); // also NaN; keeps the index arithmetic below in range
    }
    let n = res as i64;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let (i0, j0) = (x0 as i64, y0 as i64);
    let at = |i: i64, j: i64| {
        if (0..n).contains(&i) && (0..n).contains(&j) { cells[(j * n + i) as usize] } else { T::default() }
    };
    let top = at(i0, j0) * (1.0 - fx) + at(i0 + 1, j0) * fx;
    let bottom = at(i0, j0 + 1) * (1.0 - fx) + at(i0 + 1, j0 + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// True when `(x, y)` is close enough to the grid for [`bilinear`] to read a non-zero cell.
#[inline]
pub(crate) fn near_grid(res: u32, x: f32, y: f32) -> bool {
    let hi = res as f32;
    x > -1.0 && y > -1.0 && x < hi && y < hi
}
