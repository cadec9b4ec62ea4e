//! The PLY reader's memory is bounded by the size of the file (`read_ply_from` documents at most
//! about 40 bytes per byte of file): measured with a counting global allocator, on files whose
//! entries consume as few bytes as the format allows.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use dirac::io::read_ply_from;

/// The system allocator, counting the bytes in use and their peak.
struct Counting;

static IN_USE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded unchanged to the system allocator.
        let pointer = unsafe { System.alloc(layout) };
        if !pointer.is_null() {
            let now = IN_USE.fetch_add(layout.size(), Ordering::SeqCst) + layout.size();
            PEAK.fetch_max(now, Ordering::SeqCst);
        }
        pointer
    }

    unsafe fn dealloc(&self, pointer: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(pointer, layout) };
        IN_USE.fetch_sub(layout.size(), Ordering::SeqCst);
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Bytes allocated at the peak of `work`, above what was in use before it.
fn peak_of<T>(work: impl FnOnce() -> T) -> (T, usize) {
    let before = IN_USE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let result = work();
    (result, PEAK.load(Ordering::SeqCst) - before)
}

/// A binary little-endian PLY: `header` then `payload`.
fn binary_ply(elements: &str, payload: &[u8]) -> Vec<u8> {
    let mut bytes =
        format!("ply\nformat binary_little_endian 1.0\n{elements}end_header\n").into_bytes();
    bytes.extend_from_slice(payload);
    bytes
}

// One test function: the allocator's counters are process-wide, and tests run in parallel.
#[test]
fn reading_a_ply_takes_memory_proportional_to_its_size() {
    // A triangle, then a million entries of an element the mesh does not use, one byte each.
    // Parsed into general-purpose records (a map per entry), they took ~200 bytes each.
    let junk = 1_000_000;
    let mut payload = vec![0, 0, 0, 1, 0, 0, 0, 1, 0]; // three vertices of uchar x, y, z
    payload.extend_from_slice(&[3, 0, 1, 2]); // one face: uchar count, uchar indices
    payload.resize(payload.len() + junk, 7);
    let file = binary_ply(
        &format!(
            "element vertex 3\nproperty uchar x\nproperty uchar y\nproperty uchar z\n\
             element face 1\nproperty list uchar uchar vertex_indices\n\
             element junk {junk}\nproperty uchar value\n"
        ),
        &payload,
    );
    let (mesh, peak) = peak_of(|| read_ply_from(&file[..]));
    let mesh = mesh.expect("a valid PLY");
    assert_eq!(mesh.faces, [[0, 1, 2]]);
    assert!(
        peak <= 40 * file.len(),
        "{peak} bytes for a {}-byte file",
        file.len()
    );

    // As many vertices and faces as the bytes allow: three one-byte coordinates per vertex,
    // triangles of one-byte indices.
    let vertices = 200_000;
    let faces = 200_000;
    let mut payload = Vec::new();
    for v in 0..vertices {
        payload.extend_from_slice(&[(v % 251) as u8, (v % 241) as u8, (v % 239) as u8]);
    }
    for f in 0..faces {
        let base = (f % 250) as u8;
        payload.extend_from_slice(&[3, base, base + 1, base + 2]);
    }
    let file = binary_ply(
        &format!(
            "element vertex {vertices}\nproperty uchar x\nproperty uchar y\nproperty uchar z\n\
             element face {faces}\nproperty list uchar uchar vertex_indices\n"
        ),
        &payload,
    );
    let (mesh, peak) = peak_of(|| read_ply_from(&file[..]));
    let mesh = mesh.expect("a valid PLY");
    assert_eq!((mesh.positions.len(), mesh.faces.len()), (vertices, faces));
    assert_eq!(mesh.faces[3], [3, 4, 5]);
    assert_eq!(mesh.positions[7], [7.0, 7.0, 7.0]);
    assert!(
        peak <= 40 * file.len(),
        "{peak} bytes for a {}-byte file",
        file.len()
    );
}
