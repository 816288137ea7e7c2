// Bilinear sampling of cell-centred grids, zero outside: the helpers shared by glance.wgsl and
// displace.wgsl, twin of src/cpu/sample.rs (prepended to every kernel after layout.wgsl).

// True when (x, y) (continuous index coordinates: x = column, y = row, integers at cell centres)
// is close enough to a res × res grid for a bilinear read to touch a cell; false for NaN.
fn near_grid(res: u32, x: f32, y: f32) -> bool {
    let hi = f32(res);
    return x > -1.0 && y > -1.0 && x < hi && y < hi;
}

// The lower-left cell (i0, j0) of the four around (x, y) and the weights fx, fy of the upper
// neighbours; callers combine `at(i0, j0)·(1 − fx) + at(i0 + 1, j0)·fx` per row, then rows by fy.
struct Bilinear {
    i0: i32,
    j0: i32,
    fx: f32,
    fy: f32,
}

fn bilinear_at(x: f32, y: f32) -> Bilinear {
    let x0 = floor(x);
    let y0 = floor(y);
    return Bilinear(i32(x0), i32(y0), x - x0, y - y0);
}
