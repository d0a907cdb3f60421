//! A cell's faces, vertices and quarters as Portalez & Duguet number them (seed 001, Figure 4). The
//! figure is not in the text; this numbering is inferred from their tables (eqs. 8 and 9) and is the
//! one under which both tables are right in exact arithmetic (`tests/octree.rs` checks it), stated once
//! here.

/// Face `f` of a cell: the axis it is normal to.
pub const FACE_AXIS: [usize; 6] = [1, 0, 1, 0, 2, 2];
/// Face `f` of a cell: whether it lies at the high end of its axis.
pub const FACE_HIGH: [bool; 6] = [true, true, false, false, true, false];
/// Face `f`'s name in the case format.
pub const FACE_NAMES: [&str; 6] = ["+y", "+x", "-y", "-x", "+z", "-z"];

/// The face normal to `axis` at its high or low end.
pub fn face_of(axis: usize, high: bool) -> usize {
    (0..6)
        .find(|&f| FACE_AXIS[f] == axis && FACE_HIGH[f] == high)
        .expect("every axis has two faces")
}

/// The face called `name` (`-x`, `+x`, …).
pub fn face_named(name: &str) -> Option<usize> {
    FACE_NAMES.iter().position(|n| *n == name)
}

/// The two axes along a face normal to `axis`, in x, y, z order.
pub fn face_axes(axis: usize) -> [usize; 2] {
    match axis {
        0 => [1, 2],
        1 => [0, 2],
        _ => [0, 1],
    }
}

/// Quarter `j` of a face (the `j`-th of four neighbours across it, eq. 3's `N_i^j`): bit 0 set where
/// it lies on the low side of the face centre along the face's first axis ([`face_axes`]), bit 1 along
/// the second. As signs of the quarter relative to the centre: `[su, sv]`, each −1 or +1.
pub fn quarter_signs(j: usize) -> [i8; 2] {
    [
        if j & 1 == 1 { -1 } else { 1 },
        if j & 2 == 2 { -1 } else { 1 },
    ]
}

/// The quarter with signs `s` ([`quarter_signs`]).
pub(crate) fn quarter_of(s: [i8; 2]) -> usize {
    (s[0] < 0) as usize | ((s[1] < 0) as usize) << 1
}
