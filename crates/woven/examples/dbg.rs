//! scratch
use woven::fiber::*;
fn main() {
    for roughness in [0.005, 0.02, 0.1, 0.5, 2.0] {
        let f = Fiber::new(&FiberParams::rough(1.5, roughness, 0.0).with_normalization(Normalization::None), 550.0).unwrap();
        for ci in [1e-6, 1e-4, 0.003, 0.02, 0.1, 0.4, 0.8, 1.0] {
            let t = std::time::Instant::now();
            let fast = rough_single_scattering(f.alpha(), ci);
            let t1 = t.elapsed();
            let slow = single_scattering_adaptive(&f, ci, 1e-9);
            println!("r {roughness} ci {ci}: fast {fast:.10} slow {slow:.10} rel {:.2e} ({t1:?} vs {:?})", (fast-slow)/slow, t.elapsed()-t1);
        }
    }
}
