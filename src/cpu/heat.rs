//! Heat smoothing of the envelope (paper §3.2). CPU twin of `shaders/heat.wgsl`.

use super::HeatParams;

/// One explicit step `dst = src + α·Δsrc` (5-point Laplacian, zero outside the grid); with
/// `clamped = 1`, `dst = max(src, src + α·Δsrc)`.
///
/// `src` and `dst` are `res × res`, row-major, in any units (heights); α = `params.rate`,
/// stable for α ≤ ¼. The Laplacian sums `(up + down) + (left + right) − 4·centre` in that order,
/// so mirroring or transposing the input mirrors or transposes the output bit for bit. The
/// shader runs one invocation per cell; here a loop over rows, vertical neighbours first.
///
/// # Panics
///
/// If either slice is shorter than `res²`.
pub fn heat_step(params: &HeatParams, src: &[f32], dst: &mut [f32]) {
    let n = params.res as usize;
    if n == 0 {
        return;
    }
    let (src, dst) = (&src[..n * n], &mut dst[..n * n]);
    let alpha = params.rate;
    let clamped = params.clamped == 1;
    for (j, out) in dst.chunks_exact_mut(n).enumerate() {
        let row = &src[j * n..(j + 1) * n];
        // out ← up + down (rows outside the grid read as zero).
        match (j > 0, j + 1 < n) {
            (true, true) => {
                let (up, down) = (&src[(j - 1) * n..j * n], &src[(j + 1) * n..(j + 2) * n]);
                for ((o, &u), &d) in out.iter_mut().zip(up).zip(down) {
                    *o = u + d;
                }
            }
            (true, false) => out.copy_from_slice(&src[(j - 1) * n..j * n]),
            (false, true) => out.copy_from_slice(&src[n..2 * n]),
            (false, false) => out.fill(0.0),
        }
        // out ← centre + α·((up + down) + (left + right) − 4·centre).
        let update = |s: f32, vertical: f32, horizontal: f32| {
            let next = s + alpha * ((vertical + horizontal) - 4.0 * s);
            if clamped { next.max(s) } else { next }
        };
        if n == 1 {
            out[0] = update(row[0], out[0], 0.0);
            continue;
        }
        out[0] = update(row[0], out[0], row[1]);
        out[n - 1] = update(row[n - 1], out[n - 1], row[n - 2]);
        for (o, w) in out[1..n - 1].iter_mut().zip(row.windows(3)) {
            *o = update(w[1], *o, w[0] + w[2]);
        }
    }
}

/// `heat_iters` plain steps, rescale so the peak equals `dent_distance`, then `clamp_iters`
/// clamped steps, in place. An all-zero grid stays zero.
///
/// `values` is `res × res`, row-major, heights in world units; `rate` is α of
/// [`heat_step`]. Uses one scratch grid and ping-pongs between it and `values`.
///
/// # Panics
///
/// If `values` is shorter than `res²`.
pub fn heat(values: &mut [f32], res: u32, rate: f32, heat_iters: u32, clamp_iters: u32, dent_distance: f32) {
    let n = res as usize;
    let values = &mut values[..n * n];
    let mut scratch = vec![0.0f32; n * n];
    // The current grid lives in `scratch` rather than `values`.
    let mut in_scratch = false;
    let plain = HeatParams { res, rate, clamped: 0, cell_offset: 0 };
    steps(&plain, heat_iters, values, &mut scratch, &mut in_scratch);
    // Rescale the current grid; the other one is overwritten next anyway.
    let current: &mut [f32] = if in_scratch { &mut scratch } else { values };
    let peak = current.iter().fold(0.0f32, |m, &v| m.max(v));
    if peak > 0.0 {
        let scale = dent_distance / peak;
        for v in current.iter_mut() {
            *v *= scale;
        }
    }
    let clamped = HeatParams { clamped: 1, ..plain };
    steps(&clamped, clamp_iters, values, &mut scratch, &mut in_scratch);
    if in_scratch {
        values.copy_from_slice(&scratch);
    }
}

/// `count` steps of `params` ping-ponging between `values` and `scratch`; `in_scratch` says
/// which one holds the current grid and is updated.
fn steps(params: &HeatParams, count: u32, values: &mut [f32], scratch: &mut [f32], in_scratch: &mut bool) {
    for _ in 0..count {
        if *in_scratch {
            heat_step(params, scratch, values);
        } else {
            heat_step(params, values, scratch);
        }
        *in_scratch = !*in_scratch;
    }
}
