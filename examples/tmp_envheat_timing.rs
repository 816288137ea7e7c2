use dentbend::cpu::{EnvelopeParams, envelope_cols, envelope_rows, heat};
use std::time::Instant;
fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(|a, b| a.partial_cmp(b).unwrap());
    v[v.len() / 2]
}
fn main() {
    let which = std::env::args().nth(1).unwrap_or_default();
    for res in [100u32, 200, 400] {
        let n = res as usize;
        // spherical cap covering ~the grid, sigma ~ res/10 cells
        let p: Vec<f32> = (0..n * n)
            .map(|k| {
                let x = (k % n) as f32 + 0.5 - n as f32 / 2.0;
                let y = (k / n) as f32 + 0.5 - n as f32 / 2.0;
                let r = n as f32 * 0.45;
                let r2 = x * x + y * y;
                if r2 >= r * r { 0.0 } else { (0.25 - (r - (r * r - r2).sqrt()) / r).max(0.0) }
            })
            .collect();
        let mut s: u64 = 7;
        let rnd: Vec<f32> = (0..n * n)
            .map(|_| {
                s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                ((s >> 40) as f32) / 16777216.0
            })
            .collect();
        for (name, prof) in [("cap", &p), ("random", &rnd)] {
            let sigma = std::env::var("SIG").ok().map(|s| s.parse::<f32>().unwrap()).unwrap_or(n as f32 / 20.0);
            let params = EnvelopeParams { res, c: 0.5 / (sigma * sigma), _pad: [0; 2] };
            let mut rows = vec![0.0; n * n];
            let mut env = vec![0.0; n * n];
            let reps = (4_000_000 / (n * n)).max(20);
            let (mut tr, mut tc) = (vec![], vec![]);
            for _ in 0..reps {
                let t = Instant::now();
                envelope_rows(&params, prof, &mut rows);
                tr.push(t.elapsed().as_secs_f64() * 1e3);
                let t = Instant::now();
                envelope_cols(&params, &rows, &mut env);
                tc.push(t.elapsed().as_secs_f64() * 1e3);
            }
            let mut th = vec![];
            for _ in 0..reps {
                let mut v = env.clone();
                let t = Instant::now();
                heat(&mut v, res, 0.2, 8, 16, 0.25);
                th.push(t.elapsed().as_secs_f64() * 1e3);
                std::hint::black_box(&v);
            }
            if which.is_empty() || which == name {
                println!(
                    "{res}² {name}: rows {:.3} ms, cols {:.3} ms, envelope {:.3} ms, heat(8,16) {:.3} ms",
                    median(tr.clone()),
                    median(tc.clone()),
                    median(tr.iter().zip(&tc).map(|(a, b)| a + b).collect()),
                    median(th)
                );
            }
        }
    }
}
