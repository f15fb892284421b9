//! The two-thread gain the implicit solve's fork-join structure can reach on this machine:
//! the same [`over_ranges`] forks, on work that shares nothing between the ranges and is
//! split exactly in half, in passes as long as the solve's.
//!
//! Each pass reads one record of 11 numbers and one motion of 6 per particle and writes
//! another motion (about the bytes and arithmetic of a pair of the network's product),
//! then the ranges join, as a conjugate-gradient pass does. With nothing shared, what the
//! two threads lose against one is the forks and joins themselves and whatever the machine
//! takes from one core when both run.
//!
//! `cargo run --release -p sim --example fork_join_ceiling -- [particles] [passes]`
//! (default 10000 and 20000: passes of about 110 us on one thread, as the solve's at
//! N = 4000).
use sim::state::particle_ranges::over_ranges;
use std::time::Instant;

/// Arithmetic steps per particle.
const CHAIN: usize = 8;

/// One pass over `records`: `out = f(record, input)`, returning a checksum.
fn pass(records: &[[f64; 11]], input: &[[f64; 6]], out: &mut [[f64; 6]]) -> f64 {
    let mut checksum = 0.0;
    for ((r, x), o) in records.iter().zip(input).zip(out.iter_mut()) {
        let mut a = r[0] * x[0] + r[1] * x[1];
        for k in 0..CHAIN {
            a = a * r[2 + k % 9] + x[k % 6];
        }
        for (c, o) in o.iter_mut().enumerate() {
            *o = a * r[c + 2] + x[c];
        }
        checksum += a;
    }
    checksum
}

/// Seconds per pass with `threads` threads (1 or 2 ranges).
fn seconds_per_pass(n: usize, passes: usize, threads: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    pool.install(|| {
        let records: Vec<[f64; 11]> = (0..n).map(|i| [1.0 / (i as f64 + 2.0); 11]).collect();
        let mut input = vec![[0.5; 6]; n];
        let mut output = vec![[0.0; 6]; n];
        let bounds: Vec<usize> = (0..=threads).map(|k| n * k / threads).collect();
        let start = Instant::now();
        let mut checksum = 0.0;
        for _ in 0..passes {
            let inputs = &input;
            checksum += over_ranges(
                &bounds,
                &mut output[..],
                &|_, first, out: &mut [[f64; 6]]| {
                    let range = first..first + out.len();
                    pass(&records[range.clone()], &inputs[range], out)
                },
                &|a, b| a + b,
            );
            std::mem::swap(&mut input, &mut output);
        }
        std::hint::black_box(checksum);
        start.elapsed().as_secs_f64() / passes as f64
    })
}

fn main() {
    let arg = |k: usize, default: usize| {
        std::env::args()
            .nth(k)
            .map_or(Ok(default), |a| a.parse::<usize>())
    };
    let (Ok(n), Ok(passes)) = (arg(1, 10_000), arg(2, 20_000)) else {
        eprintln!("usage: fork_join_ceiling [particles] [passes] (whole numbers)");
        std::process::exit(2);
    };
    if n < 2 || passes == 0 {
        eprintln!("need at least 2 particles and 1 pass");
        std::process::exit(2);
    }
    for run in 1..=3 {
        let one = seconds_per_pass(n, passes, 1);
        let two = seconds_per_pass(n, passes, 2);
        println!(
            "run {run}: {n} particles, pass {:.1} us on 1 thread, {:.1} us on 2: gain {:.2}x",
            one * 1e6,
            two * 1e6,
            one / two
        );
    }
}
