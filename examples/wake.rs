use std::time::{Duration, Instant};
fn work(us: u64) -> u64 {
    let t = Instant::now();
    let mut x = 0u64;
    while t.elapsed() < Duration::from_micros(us) {
        x = x.wrapping_add(1);
    }
    x
}
fn main() {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    for gap_us in [0u64, 20, 100, 1000] {
        let mut total = Duration::ZERO;
        let n = 200;
        for _ in 0..n {
            work(gap_us); // serial gap on main thread
            let t = Instant::now();
            pool.install(|| rayon::join(|| work(100), || work(100)));
            total += t.elapsed();
        }
        println!(
            "gap {gap_us:5} us: join of 2x100us took {:.1} us on average",
            total.as_secs_f64() * 1e6 / n as f64
        );
    }
}
