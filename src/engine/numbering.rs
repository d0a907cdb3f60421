//! Which face numbering a method's answers keep: well-shaped cases asked under every relabelling of
//! the four faces (an answerer's `--faces auto`, the conformance kit's convention check; each probes
//! another orientation its own way where none fits).

use crate::choice::Choice;
use crate::family::contract::{Contract, Orientation};
use crate::family::{Family, Verdict};

/// Well-shaped cases asked under each face numbering tried.
pub(crate) const NUMBERING_CASES: usize = 2000;

/// How a method fared on well-shaped cases under each face numbering.
struct Scores {
    /// Each numbering and the cases it answered rightly under it, best first.
    ranked: Vec<([u8; 4], usize)>,
    /// Cases whose line crosses the tetrahedron (the others are not judged).
    judged: usize,
    /// Of those, the ones it answered with no exit face (under the identity numbering).
    none: usize,
}

impl Scores {
    /// The numbering right on at least 99% of judged cases with no other within 1%.
    fn fits(&self) -> Option<[u8; 4]> {
        let ([(best, right), (_, second), ..], judged) = (&self.ranked[..], self.judged.max(1))
        else {
            return None;
        };
        (right * 100 >= judged * 99 && (right - second) * 100 >= judged).then_some(*best)
    }
}

/// The answers to `cases` under every face numbering `p`: `ask(cases, p)` sends each case in that
/// numbering (its entry face renumbered, [`Family::for_program`]) and returns the answers as the
/// method numbers faces, read back through `p` here.
fn scores<F: Family, E>(
    cases: &[(F::Case, F::Truth)],
    ask: &mut impl FnMut(&[F::Case], &[u8; 4]) -> Result<Vec<F::Answer>, E>,
) -> Result<Scores, E> {
    let plain: Vec<F::Case> = cases.iter().map(|(c, _)| *c).collect();
    let mut ranked = Vec::new();
    let (mut none, mut judged) = (0, 0);
    for p in permutations() {
        let raw = ask(&plain, &p)?;
        let verdicts: Vec<Verdict> = cases
            .iter()
            .zip(&raw)
            .map(|((c, x), f)| F::verdict(c, x, &F::renumbered(*f, &p)))
            .collect();
        if p == IDENTITY {
            none = verdicts
                .iter()
                .filter(|v| **v == Verdict::Wrong(crate::walk::OutcomeKind::NoExitFace))
                .count();
            judged = verdicts
                .iter()
                .filter(|v| **v != Verdict::NotJudged)
                .count();
        }
        ranked.push((p, verdicts.iter().filter(|v| **v == Verdict::Right).count()));
    }
    ranked.sort_by_key(|&(_, r)| std::cmp::Reverse(r));
    Ok(Scores {
        ranked,
        judged,
        none,
    })
}

/// tetwalk's own numbering: face `i` opposite vertex `i`.
pub(crate) const IDENTITY: [u8; 4] = [0, 1, 2, 3];

/// What the search found.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Numbering {
    /// The method's face `i` is the case's face `p[i]`.
    Fits([u8; 4]),
    /// No numbering fits.
    NoFit {
        /// The best numbering, and the cases it answered rightly.
        best: ([u8; 4], usize),
        /// The next best's right answers.
        next: usize,
        /// Cases judged (their line crosses the tetrahedron).
        judged: usize,
        /// It answered no exit face on every judged case.
        no_face: bool,
    },
}

impl Numbering {
    /// Why no numbering fits, in words, for cases of contract `k` (`asked` of them); `mirrored` is
    /// the other orientation tried and the numbering that fits it, if one does, and `advice` says how
    /// to ask for orientation `o` and numbering `p` where one does.
    pub(crate) fn why(
        &self,
        k: &Contract,
        asked: usize,
        mirrored: Option<(Orientation, Option<[u8; 4]>)>,
        advice: impl Fn(Orientation, [u8; 4]) -> String,
    ) -> String {
        let Numbering::NoFit {
            best: (best, right),
            next,
            judged,
            no_face,
        } = self
        else {
            return format!("the face numbering {self:?} fits");
        };
        let mut why = format!(
            "no face numbering fits its answers to {asked} well-shaped cases ({}): the best, answered face i = case face {best:?}[i], is right on {right} of {judged} judged (the next {next})",
            k.describe(),
        );
        if *no_face {
            why += &format!(
                "; it answered no exit face on every one of the {judged} cases, each of which its line crosses: does it read the cases as sent (docs/answerers.md: --answerer-format, each binary record beginning with the case's number)?"
            );
        } else {
            match mirrored {
                Some((o, Some(p))) => {
                    why += &format!(
                        "; with the tetrahedra mirrored it fits: it takes {} tetrahedra ({})",
                        o.name(),
                        advice(o, p)
                    );
                }
                Some((o, None)) => {
                    why += &format!(" (nor does any fit {} tetrahedra)", o.name());
                }
                None => {}
            }
        }
        why
    }
}

/// The face numbering under which `ask` (as [`scores`] calls it) answers well-shaped cases of family
/// `F` holding contract `k` rightly ([`Family::numbering_cases`]): every relabelling of the four
/// faces tried, the one right on at least 99% of judged cases with no other within 1%; where none
/// fits, the best. With the number of cases asked.
pub(crate) fn find<F: Family, E>(
    k: &Contract,
    mut ask: impl FnMut(&[F::Case], &[u8; 4]) -> Result<Vec<F::Answer>, E>,
) -> Result<(Numbering, usize), E> {
    let cases = F::numbering_cases(k, NUMBERING_CASES);
    let s = scores::<F, E>(&cases, &mut ask)?;
    let found = match s.fits() {
        Some(p) => Numbering::Fits(p),
        None => Numbering::NoFit {
            best: s.ranked[0],
            next: s.ranked[1].1,
            judged: s.judged,
            no_face: s.none == s.judged && s.judged > 0,
        },
    };
    Ok((found, cases.len()))
}

/// The 24 orderings of four faces.
fn permutations() -> Vec<[u8; 4]> {
    let mut out = Vec::new();
    for a in 0..4u8 {
        for b in 0..4u8 {
            for c in 0..4u8 {
                // The fourth is the one left: 0 + 1 + 2 + 3 = 6 (checked: the first three may sum
                // past 6).
                let Some(d) = 6u8.checked_sub(a + b + c) else {
                    continue;
                };
                if a != b && a != c && b != c && d < 4 && d != a && d != b && d != c {
                    out.push([a, b, c, d]);
                }
            }
        }
    }
    out
}

/// A face numbering `--faces` gives: four distinct faces, `a,b,c,d` (answered face i is case face
/// the i-th).
pub(crate) fn parse_faces(s: &str) -> Result<[u8; 4], String> {
    let f: Vec<u8> = s
        .split(',')
        .map(|x| x.trim().parse::<u8>().ok().filter(|&f| f < 4))
        .collect::<Option<_>>()
        .ok_or_else(|| format!("'{s}' is not four faces 0..3, comma-separated"))?;
    match f[..] {
        [a, b, c, d] if permutations().contains(&[a, b, c, d]) => Ok([a, b, c, d]),
        _ => Err(format!("'{s}' is not an ordering of the faces 0,1,2,3")),
    }
}

#[cfg(test)]
mod tests {
    /// The 24 orderings, each once (in a debug build the sum of three faces past 6 overflowed).
    #[test]
    fn the_face_orderings_are_the_24_permutations() {
        let p = super::permutations();
        let distinct: std::collections::HashSet<_> = p.iter().collect();
        assert_eq!((p.len(), distinct.len()), (24, 24));
        for q in &p {
            let mut sorted = *q;
            sorted.sort();
            assert_eq!(sorted, [0, 1, 2, 3], "{q:?}");
        }
    }
}
