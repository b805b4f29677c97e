//! Priority-flood, D8 routing with accumulation, and one stream-power step at 1024², 2048² and
//! 4096² on an fBm terrain full of pits (`relief_fixtures::pitted_fbm_dem`: about 28 % of its
//! cells lie in depressions). Target (issue #6): 4096² flood + accumulation under 3 s. Beside ours
//! runs the textbook Priority-Flood+ε of Barnes, Lehman & Mulla (2014, Algorithm 3: binary heap and
//! pit queue).

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use relief_fixtures::pitted_fbm_dem;
use relief_heightfield::Heightfield;
use relief_hydrology::{D8, Outlets, StreamPower, fill};

/// Barnes et al.'s Priority-Flood+ε as published: every border cell seeds a binary heap; raised
/// cells go through a pit queue.
fn textbook_fill(dem: &Heightfield) -> Vec<f32> {
    let (nx, ny) = (dem.nx(), dem.ny());
    let mut z = dem.samples().to_vec();
    let mut closed = vec![false; z.len()];
    let mut open = BinaryHeap::new();
    let mut pit = VecDeque::new();
    let key = |v: f32| {
        let b = v.to_bits();
        if b & 0x8000_0000 != 0 { !b } else { b | 0x8000_0000 }
    };
    for j in 0..ny {
        for i in 0..nx {
            if i == 0 || j == 0 || i + 1 == nx || j + 1 == ny {
                let k = j * nx + i;
                closed[k] = true;
                open.push(Reverse((key(z[k]), k as u32)));
            }
        }
    }
    loop {
        let k = if let Some(k) = pit.pop_front() {
            k
        } else if let Some(Reverse((_, k))) = open.pop() {
            k as usize
        } else {
            break;
        };
        let (i, j) = ((k % nx) as i64, (k / nx) as i64);
        for (di, dj) in [(-1, 0), (1, 0), (0, -1), (0, 1), (-1, -1), (1, 1), (-1, 1), (1, -1)] {
            let (a, b) = (i + di, j + dj);
            if a < 0 || b < 0 || a >= nx as i64 || b >= ny as i64 {
                continue;
            }
            let w = b as usize * nx + a as usize;
            if closed[w] {
                continue;
            }
            closed[w] = true;
            if z[w] <= z[k].next_up() {
                z[w] = z[k].next_up();
                pit.push_back(w);
            } else {
                open.push(Reverse((key(z[w]), w as u32)));
            }
        }
    }
    z
}

/// `cargo xtask bench --quick` sets `RELIEF_BENCH_QUICK`: the largest sizes are skipped then.
fn quick() -> bool {
    std::env::var_os("RELIEF_BENCH_QUICK").is_some()
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("hydrology");
    group.sample_size(10);
    let largest = if quick() { 1024 } else { 4096 };
    for n in [1024usize, 2048, 4096].into_iter().filter(|&n| n <= largest) {
        let dem = pitted_fbm_dem(n).expect("terrain");
        group.bench_with_input(BenchmarkId::new("priority_flood", n), &dem, |b, dem| {
            b.iter(|| black_box(fill(dem, Outlets::new()).expect("fill")));
        });
        group.bench_with_input(BenchmarkId::new("textbook_priority_flood", n), &dem, |b, dem| {
            b.iter(|| black_box(textbook_fill(dem)));
        });
        let filled = fill(&dem, Outlets::new()).expect("fill");
        group.bench_with_input(BenchmarkId::new("d8_accumulation", n), &filled, |b, filled| {
            b.iter(|| black_box(D8::new(filled).expect("d8").drainage_area()[0]));
        });
        group.bench_with_input(BenchmarkId::new("flood_and_accumulation", n), &dem, |b, dem| {
            b.iter(|| black_box(D8::new(&fill(dem, Outlets::new()).expect("fill")).expect("d8").drainage_area()[0]));
        });
        let sp = StreamPower::default();
        group.bench_with_input(BenchmarkId::new("stream_power_step", n), &dem, |b, dem| {
            b.iter_batched(
                || dem.clone(),
                |mut h| {
                    sp.step(&mut h).expect("step");
                    black_box(h)
                },
                criterion::BatchSize::LargeInput,
            );
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
