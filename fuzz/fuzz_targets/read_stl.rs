//! The STL reader (ASCII and binary), and validation of whatever it parses, never panic.
#![no_main]

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    if let Ok(raw) = dirac::io::read_stl_from(data) {
        let _ = raw.clone().into_mesh();
        if let Ok((mesh, _)) = raw.into_mesh_removing_unreferenced() {
            let _ = mesh.topology();
        }
    }
});
