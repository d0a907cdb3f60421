//! The conformance kit's entry points for this family (a file of the kit layer in the family's
//! folder; `crate::kit` re-exports its public items from the families' list).

use super::ExitFace;
use crate::family::Walks;
use crate::kit::run::{and_then, check, check_case, check_with, faces_list, kit_case};
use crate::kit::{Failed, Passed, Settings, short_name};
use crate::methods::ExitMethod;
use crate::registry::Method;
use crate::tet::Case;

kit_case!(Case, ExitFace);

/// Judge exit-face method `M` exactly: the convention check (face numbering and orientation), every
/// stress row of tetrahedron cases, a property campaign through the `exit_face` fuzz target's
/// generator, then walks through the lattice-tie scenes (a cycle or step limit is an endless walk) and
/// a property campaign through the `walk` target's.
pub fn exit_faces<M: ExitMethod>(s: &Settings) -> Result<Passed, Box<Failed>> {
    let m = Method::outside::<M>(short_name::<M>());
    let first = check_with::<ExitFace>(&m, s, |_| negatively_oriented(&m, s));
    and_then(s, first, || check::<Walks>(&m, s))
}

/// Where a method's answers fit no face numbering of the positively oriented tetrahedra it is
/// handed: whether they fit the same tetrahedra mirrored (vertices 0 and 1 swapped, so negatively
/// oriented), and under which numbering — said as what the method must do.
fn negatively_oriented(m: &Method, s: &Settings) -> Option<String> {
    use crate::engine::numbering::{IDENTITY, Numbering, find};
    use crate::family::Family;
    use crate::tet::SWAP01;
    let exit = m.exit(s.model);
    let ask = |cases: &[Case], p: &[u8; 4]| {
        let answers = cases.iter().map(|c| {
            let (tet, entry, map) = crate::cases::normalized(&ExitFace::for_program(c, p));
            let mut mirrored = tet;
            mirrored.swap(0, 1);
            // Its face f of the mirrored tetrahedron is the handed one's face SWAP01[f].
            exit(&mirrored, &c.ray(), entry.map(|e| SWAP01[e])).map(|f| map[SWAP01[f]] as u8)
        });
        Ok::<_, std::convert::Infallible>(answers.collect())
    };
    let k = crate::family::contract::Contract {
        orientation: crate::family::contract::Orientation::Positive,
        ..s.contract
    };
    let Ok((Numbering::Fits(p), asked)) = find::<ExitFace, _>(&k, ask) else {
        return None;
    };
    let numbering = match p {
        IDENTITY => String::new(),
        p => format!(", and its face i is tetwalk's face {}[i]", faces_list(p)),
    };
    Some(format!(
        "its answers fit none of tetwalk's face numberings, but on {asked} well-shaped cases ({}) they fit the tetrahedra mirrored: it takes negatively oriented tetrahedra{numbering}, where `ExitMethod::exit_face` is handed positively oriented ones (orient3d(v0, v1, v2, v3) > 0, face i opposite vertex i); swap vertices 0 and 1 (and faces 0 and 1) inside it",
        s.contract.describe()
    ))
}

/// Judge exit-face method `M` on one tetrahedron case (a property test's, or a reported case read
/// back with [`crate::kit::KitCase::from_line`] in a regression test): `Ok` where its exit face is
/// right or the line misses the tetrahedron, else the failure, shrunk.
pub fn judge_exit_face<M: ExitMethod>(case: &Case, s: &Settings) -> Result<(), Box<Failed>> {
    check_case::<ExitFace>(&Method::outside::<M>(short_name::<M>()), case, s)
}
