//! The structured solver's kernels against this machine's limits (issue #43's roofline table):
//! `cargo run --release --example roofline [SCENE or built-in spec …]` (default: the Armadillo, pyramid8 and
//! cone). Prints the machine's bandwidth (STREAM's scale) over a kernel's working set and its
//! peak multiply–add rates (SSE2 as this crate is compiled, AVX2+FMA as the CPU allows),
//! then per kernel: calls, time per call, flops and bytes per call (leading terms,
//! `kernel_profile::Kernel::cost`), the achieved rates, the bound and how far from it.
use std::hint::black_box;
use std::time::{Duration, Instant};
use voussoir::interfaces::detect;
use voussoir::io::load_scene;
use voussoir::model::{Assembly, builtin};
use voussoir::statics::kernel_profile::{self, Kernel};
use voussoir::statics::{self, FrictionModel, StaticsSettings};

/// The fastest of `runs` timings of `f`.
fn best(runs: usize, mut f: impl FnMut()) -> Duration {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed()
        })
        .min()
        .unwrap_or_default()
}

/// STREAM's scale, b = s·a: bytes read and written per second over `bytes` bytes in all (not
/// `copy_from_slice`: glibc's memcpy takes `rep movsb` for mid sizes, which is slow on this VM).
fn copy_rate(bytes: usize) -> f64 {
    let n = (bytes / 16).max(64);
    let a: Vec<f64> = (0..n).map(|i| i as f64).collect();
    let mut b = vec![0.0f64; n];
    let reps = (64 << 20) / (16 * n) + 1;
    let t = best(7, || {
        for _ in 0..reps {
            let s = black_box(1.000_001);
            for (o, x) in b.iter_mut().zip(black_box(&a)) {
                *o = s * x;
            }
            black_box(&mut b);
        }
    });
    (16 * n * reps) as f64 / t.as_secs_f64()
}

#[cfg(target_arch = "x86_64")]
mod simd {
    use std::arch::x86_64::*;

    /// 10 independent chains of packed multiply then add (SSE2: 2 lanes).
    pub fn sse2(n: usize) -> f64 {
        // SAFETY: SSE2 is part of the x86_64 baseline.
        unsafe {
            let (x, y) = (_mm_set1_pd(0.999_999), _mm_set1_pd(1e-7));
            let mut a = [_mm_set1_pd(1.0); 10];
            for _ in 0..n {
                for v in a.iter_mut() {
                    *v = _mm_add_pd(_mm_mul_pd(*v, x), y);
                }
            }
            let mut s = [0.0f64; 2];
            _mm_storeu_pd(s.as_mut_ptr(), a.iter().fold(_mm_setzero_pd(), |s, v| _mm_add_pd(s, *v)));
            s[0] + s[1]
        }
    }

    /// 10 independent chains of fused multiply–adds (AVX2+FMA: 4 lanes).
    #[target_feature(enable = "avx2,fma")]
    pub fn fma(n: usize) -> f64 {
        let (x, y) = (_mm256_set1_pd(0.999_999), _mm256_set1_pd(1e-7));
        let mut a = [_mm256_set1_pd(1.0); 10];
        for _ in 0..n {
            for v in a.iter_mut() {
                *v = _mm256_fmadd_pd(*v, x, y);
            }
        }
        let mut s = [0.0f64; 4];
        // SAFETY: `s` holds four f64.
        unsafe { _mm256_storeu_pd(s.as_mut_ptr(), a.iter().fold(_mm256_setzero_pd(), |s, v| _mm256_add_pd(s, *v))) };
        s.iter().sum()
    }
}

/// Peak packed rates (flops per second): SSE2 as compiled, and AVX2+FMA when the CPU has it.
fn simd_peaks() -> (f64, Option<f64>) {
    let n = 4_000_000usize;
    #[cfg(target_arch = "x86_64")]
    {
        let t = best(3, || {
            black_box(simd::sse2(black_box(n)));
        });
        let sse2 = (n * 10 * 2 * 2) as f64 / t.as_secs_f64();
        let fma = is_x86_feature_detected!("fma").then(|| {
            let t = best(3, || {
                // SAFETY: the CPU reports AVX2 and FMA.
                black_box(unsafe { simd::fma(black_box(n)) });
            });
            (n * 10 * 4 * 2) as f64 / t.as_secs_f64()
        });
        (sse2, fma)
    }
    #[cfg(not(target_arch = "x86_64"))]
    (f64::NAN, None)
}

fn main() {
    let root = env!("CARGO_MANIFEST_DIR");
    let args: Vec<String> = std::env::args().skip(1).collect();
    let scenes =
        if args.is_empty() { vec![format!("{root}/assets/compas/compas_cra/armadillo_cra.json")] } else { args };
    let (sse2, fma) = simd_peaks();
    let fma_text = fma.map_or("-".into(), |f| format!("{:.1}", f / 1e9));
    println!("peak multiply-add: SSE2 {:.1} GFLOP/s, AVX2+FMA {fma_text}", sse2 / 1e9);
    for kb in [64usize, 256, 1024, 4096, 65536] {
        println!("scale over {kb:6} KiB: {:6.1} GB/s", copy_rate(kb << 10) / 1e9);
    }
    let limit_flops = fma.unwrap_or(sse2);
    for path in scenes {
        let file = std::path::Path::new(&path);
        let scene = if file.exists() {
            load_scene(file).expect("scene loads")
        } else {
            builtin(&path).expect("a built-in scene")
        };
        let asm = Assembly::new(&scene, &Default::default()).expect("assembly");
        let ifs = detect(&asm);
        for (model, blocks) in
            [FrictionModel::Pyramid8, FrictionModel::Cone].into_iter().flat_map(|m| [(m, true), (m, false)])
        {
            kernel_profile::factor_by_blocks(blocks);
            let settings = StaticsSettings { friction_model: model, ..Default::default() };
            let runs: usize = std::env::var("ROOFLINE_RUNS").ok().and_then(|r| r.parse().ok()).unwrap_or(7);
            statics::solve(&asm, &ifs, &settings).expect("solves");
            kernel_profile::enable(true);
            let _ = kernel_profile::take();
            let mut iterations = 0;
            for _ in 0..runs {
                iterations = statics::solve(&asm, &ifs, &settings).expect("solves").solver.iterations;
            }
            kernel_profile::enable(false);
            let prof = kernel_profile::take();
            let factor = if blocks { "S by 6×6 blocks" } else { "S by faer" };
            report(&format!("{path} ({factor})"), model, &prof, runs, iterations, limit_flops);
        }
    }
}

fn report(path: &str, model: FrictionModel, prof: &kernel_profile::Profile, runs: usize, iterations: u32, peak: f64) {
    let d = prof.dims;
    let name = path.rsplit('/').next().unwrap_or(path);
    println!(
        "\n{name} {model}: {} points × {} variables, {} rows each; S {}×{} ({} entries, factor {}, {:.1} Mflop); {iterations} iterations",
        d.points,
        d.per_point,
        d.rows_per_point,
        d.m_e,
        d.m_e,
        d.s_values,
        d.l_values,
        d.factor_flops / 1e6
    );
    println!(
        "{:16} {:>6} {:>9} {:>9} {:>9} {:>9} {:>8} {:>8} {:>7} {:>7} {:>8}",
        "kernel", "calls", "ms/solve", "µs/call", "kflop", "kB", "GFLOP/s", "GB/s", "flop/B", "bound", "of limit"
    );
    let (solve, _) = prof.of(Kernel::Solve);
    let mut counted = Duration::ZERO;
    for k in Kernel::ALL {
        let (t, calls) = prof.of(k);
        if k != Kernel::Solve {
            counted += t;
        }
        let per_solve = t.as_secs_f64() * 1e3 / runs as f64;
        let per_call = t.as_secs_f64() / calls.max(1) as f64;
        let Some((flops, bytes)) = k.cost(&d) else {
            println!("{:16} {:>6} {:>9.2}", format!("{k:?}"), calls / runs as u64, per_solve);
            continue;
        };
        let (gflops, gbs) = (flops / per_call / 1e9, bytes / per_call / 1e9);
        let bandwidth = copy_rate(bytes as usize);
        // Roofline: the attainable rate at this intensity is min(peak, intensity × bandwidth).
        let intensity = flops / bytes;
        let attainable = peak.min(intensity * bandwidth);
        let bound = if intensity * bandwidth < peak { "memory" } else { "compute" };
        println!(
            "{:16} {:>6} {:>9.2} {:>9.1} {:>9.1} {:>9.1} {:>8.2} {:>8.1} {:>7.2} {:>7} {:>7.0}%",
            format!("{k:?}"),
            calls / runs as u64,
            per_solve,
            per_call * 1e6,
            flops / 1e3,
            bytes / 1e3,
            gflops,
            gbs,
            intensity,
            bound,
            100.0 * flops / per_call / attainable
        );
    }
    let other = solve.saturating_sub(counted);
    println!("{:16} {:>6} {:>9.2}", "(vector work)", "", other.as_secs_f64() * 1e3 / runs as f64);
}
