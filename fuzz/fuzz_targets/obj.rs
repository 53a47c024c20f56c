//! OBJ meshes: any bytes give a sound mesh (indices in range, finite positions, normals and uv
//! one per vertex or none) or an error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use woven::Vec3;
use woven_render::shapes::read_obj;

fuzz_target!(|data: &[u8]| {
    if let Ok(mesh) = read_obj(data, "<fuzz>", 1.0, Vec3::new(0.0, 0.0, 0.0), "shape[0].file") {
        let n = mesh.positions.len();
        assert!(!mesh.indices.is_empty());
        assert!(mesh.indices.iter().flatten().all(|&i| (i as usize) < n));
        assert!(mesh
            .positions
            .iter()
            .all(|p| p.x.is_finite() && p.y.is_finite() && p.z.is_finite()));
        assert!(mesh.normals.is_empty() || mesh.normals.len() == n);
        assert!(mesh.uvs.is_empty() || mesh.uvs.len() == n);
    }
});
