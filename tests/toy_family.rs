//! A fourth family defined here, outside tetwalk: through which end of a segment on the x axis a ray
//! leaves. It implements `Family` and nothing else, and gets tetwalk's stress runs, campaigns,
//! standings, found cases and their replay, and the conformance kit for free — the measure of the
//! family abstraction.

use glam::Vec3;
use rand::RngExt;
use serde_json::{Map, Value, json};
use tetwalk::backend::{Backend, BackendError, CPU};
use tetwalk::cases::{CaseError, field_error, number};
use tetwalk::engine::found::{Found, Replay, check, replay};
use tetwalk::engine::standing::Standings;
use tetwalk::engine::stress::{self, StressSettings};
use tetwalk::family::{Family, Summed, Verdict};
use tetwalk::kit::{self, Settings};
use tetwalk::registry::{Claim, GpuVersion, Info, Named};
use tetwalk::tet::Ray;
use tetwalk::walk::OutcomeKind;

/// Segments and rays on the x axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Segments;

/// A segment `[lo, hi]` and a ray along the x axis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Segment {
    lo: f32,
    hi: f32,
    org: f32,
    dir: f32,
}

/// A method: which end the ray leaves through (0 the low end, 1 the high one), or none.
struct EndMethod {
    info: Info,
    end: fn(&Segment) -> Option<u8>,
}

impl Named for EndMethod {
    fn info(&self) -> &Info {
        &self.info
    }
}

const fn info(name: &'static str) -> Info {
    Info::published(name, "a toy of this test", GpuVersion::CpuOnly("a toy"))
}

/// By the direction's sign, exactly.
fn by_sign(s: &Segment) -> Option<u8> {
    (s.dir != 0.0).then_some((s.dir > 0.0) as u8)
}

/// As a GPU that flushes subnormals would see the direction: none where it is subnormal.
fn flushed(s: &Segment) -> Option<u8> {
    (s.dir.is_normal()).then_some((s.dir > 0.0) as u8)
}

static METHODS: [EndMethod; 2] = [
    EndMethod {
        info: info("by-sign").claiming(Claim::Robust),
        end: by_sign,
    },
    EndMethod {
        info: info("flushed"),
        end: flushed,
    },
];

/// The rows: ordinary directions, and subnormal ones.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
struct ToyRow {
    directions: &'static str,
}

#[derive(Clone, Debug, Default, serde::Serialize)]
struct ToyRows;

#[derive(Clone, Debug, Default, serde::Serialize)]
struct ToyTally {
    judged: u64,
    wrong: u64,
}

impl Summed for ToyTally {
    fn add(&mut self, o: &Self) {
        self.judged += o.judged;
        self.wrong += o.wrong;
    }
}

impl Family for Segments {
    const NAME: &'static str = "segment";
    const FUZZ_TARGET: &'static str = "segment";
    const BYTES_PER_CASE: u128 = 64;

    type Method = EndMethod;
    type Case = Segment;
    type Truth = Option<u8>;
    type Answer = Option<u8>;
    type Rows = ToyRows;
    type Row = ToyRow;
    type RowFacts = ();
    type Tally = ToyTally;

    fn methods() -> &'static [EndMethod] {
        &METHODS
    }

    fn owns(obj: &Map<String, Value>) -> bool {
        obj.contains_key("segment")
    }

    fn take_case(obj: &mut Map<String, Value>) -> Result<Segment, CaseError> {
        let mut field = |k: &'static str| obj.remove(k).ok_or(CaseError::Missing(k));
        let seg = field("segment")?;
        let ends = seg
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| field_error("segment", "must hold two ends"))?;
        let x = |v: &Value, at: &str| number(v).map_err(|e| field_error(at, e));
        Ok(Segment {
            lo: x(&ends[0], "segment[0]")?,
            hi: x(&ends[1], "segment[1]")?,
            org: x(&field("org")?, "org")?,
            dir: x(&field("dir")?, "dir")?,
        })
    }

    fn case_json(s: &Segment) -> Map<String, Value> {
        match json!({"segment": [s.lo, s.hi], "org": s.org, "dir": s.dir}) {
            Value::Object(m) => m,
            _ => Map::new(),
        }
    }

    fn ray(s: &Segment) -> Ray {
        Ray {
            org: Vec3::new(s.org, 0.0, 0.0),
            dir: Vec3::new(s.dir, 0.0, 0.0),
        }
    }

    fn with_ray(s: &Segment, ray: Ray) -> Segment {
        Segment {
            org: ray.org.x,
            dir: ray.dir.x,
            ..*s
        }
    }

    fn truth(s: &Segment) -> Result<Option<u8>, CaseError> {
        if s.lo >= s.hi {
            return Err(field_error(
                "segment",
                "the low end is not below the high one",
            ));
        }
        Ok(by_sign(s))
    }

    fn verdict(_: &Segment, truth: &Option<u8>, answer: &Option<u8>) -> Verdict {
        match truth {
            None => Verdict::NotJudged,
            t if t == answer => Verdict::Right,
            _ => Verdict::Wrong(Self::kind(answer)),
        }
    }

    fn right_answers(_: &Segment, truth: &Option<u8>) -> String {
        format!("end {truth:?}")
    }

    fn answers(
        _: &Backend,
        m: &EndMethod,
        cases: &[Segment],
    ) -> Result<Vec<Option<u8>>, BackendError> {
        Ok(cases.iter().map(m.end).collect())
    }

    fn kind(a: &Option<u8>) -> OutcomeKind {
        match a {
            Some(_) => OutcomeKind::Hit,
            None => OutcomeKind::NoExitFace,
        }
    }

    fn answer_json(a: &Option<u8>) -> Value {
        json!(a)
    }

    fn parse_answer(v: &Value, _: &Segment) -> Result<Option<u8>, String> {
        match v {
            Value::Null => Ok(None),
            e => e
                .as_u64()
                .filter(|&e| e < 2)
                .map(|e| Some(e as u8))
                .ok_or_else(|| format!("{e} is not an end 0 or 1")),
        }
    }

    fn given(obj: &Map<String, Value>, s: &Segment) -> Result<Option<u8>, String> {
        Self::parse_answer(obj.get("end").unwrap_or(&Value::Null), s)
    }

    fn describe(a: &Option<u8>) -> String {
        format!("end {a:?}")
    }

    fn rows(_: &ToyRows) -> Vec<ToyRow> {
        vec![
            ToyRow {
                directions: "ordinary",
            },
            ToyRow {
                directions: "subnormal",
            },
        ]
    }

    fn row_name(r: &ToyRow) -> String {
        r.directions.to_string()
    }

    fn case(_: &ToyRows, row: ToyRow, seed: u64, i: usize) -> Option<(Segment, Option<u8>)> {
        let mut r = tetwalk::scenes::rng(seed ^ (i as u64) << 1 ^ (row.directions.len() as u64));
        let lo = r.random_range(-4.0..0.0f32);
        let scale = match row.directions {
            "ordinary" => 1.0,
            _ => f32::MIN_POSITIVE / 8.0,
        };
        let dir = r.random_range(-1.0..1.0f32) * scale;
        let s = Segment {
            lo,
            hi: lo + 8.0,
            org: lo + 4.0,
            dir,
        };
        Some((s, Self::truth(&s).ok()?))
    }

    fn tally(t: &mut ToyTally, s: &Segment, truth: &Option<u8>, answer: &Option<u8>) {
        match Self::verdict(s, truth, answer) {
            Verdict::NotJudged => {}
            Verdict::Right => t.judged += 1,
            Verdict::Wrong(_) => {
                t.judged += 1;
                t.wrong += 1;
            }
        }
    }

    fn judged(_: &(), t: &ToyTally) -> u64 {
        t.judged
    }

    fn wrong(t: &ToyTally) -> u64 {
        t.wrong
    }

    fn arbitrary(u: &mut arbitrary::Unstructured) -> Option<Segment> {
        let lo: f32 = u.arbitrary().ok()?;
        let dir: f32 = u.arbitrary().ok()?;
        let s = Segment {
            lo,
            hi: lo + 1.0,
            org: lo,
            dir,
        };
        (lo.is_finite() && dir.is_finite() && s.hi > lo).then_some(s)
    }
}

fn settings() -> StressSettings<Segments> {
    StressSettings {
        contract: Default::default(),
        cases: 500,
        rows: ToyRows,
        seed: 3,
        backend: CPU.ran(),
        scale: Default::default(),
    }
}

/// Stress, the standings and a campaign, as `tetwalk stress` runs them.
#[test]
fn a_toy_family_gets_stress_tables_and_campaigns() {
    let methods: Vec<&EndMethod> = METHODS.iter().collect();
    let mut wrong = 0;
    let report = stress::run(
        &settings(),
        &stress::Who::methods(&methods),
        &CPU,
        &|_| {},
        &mut |w| {
            assert_eq!(w.who.name(), "flushed");
            wrong += 1;
        },
    )
    .unwrap();
    let flushed =
        |r: &stress::StressReport<Segments>, row: usize| r.rows[row].tallies[1].counts.wrong;
    assert_eq!(report.rows[0].tallies[0].counts.judged, 500);
    assert_eq!(flushed(&report, 0), 0, "ordinary directions are right");
    assert!(
        flushed(&report, 1) > 400,
        "subnormal directions are flushed"
    );
    assert_eq!(wrong, flushed(&report, 1));
    let standings = report.standings();
    assert_eq!(
        standings[0].line(),
        "by-sign: 0 wrong of 1000 judged; claims robust: holds here"
    );
    assert!(!standings[1].refuted() && standings[1].wrong > 0);
    let campaign = stress::campaign(
        &settings(),
        &stress::Who::methods(&methods),
        &CPU,
        0.0,
        &|_| {},
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(campaign.rounds, 1);
    let json = serde_json::to_value(&campaign).unwrap();
    assert_eq!(json["rows"][1]["directions"], "subnormal");
    assert_eq!(json["rows"][1]["tallies"][1]["method"], "flushed");
}

/// A failure filed as a found case reads back, replays with its recorded answer, notices a changed
/// one, and shrinks; the claim-holding method is filed beside it only where it fails too.
#[test]
fn a_toy_family_gets_found_cases_and_replay() {
    let (cases, _) = stress::row_cases(
        &settings(),
        ToyRow {
            directions: "subnormal",
        },
    );
    let batch: Vec<Segment> = cases.iter().map(|(c, _)| *c).collect();
    let held = [(&METHODS[1], tetwalk::engine::found::Hold::Every)];
    let (i, failure) = check::<Segments>(&batch, &held, &[&CPU]).unwrap().unwrap();
    let found = Found::of(batch[i], failure);
    let line = found.to_json();
    assert!(
        line.contains("\"segment\"") && line.contains("\"kind\":\"no_exit_face\""),
        "{line}"
    );
    let read = Found::<Segments>::parse(&line).unwrap();
    assert_eq!(read, found);
    assert_eq!(replay(&read).unwrap(), Replay::Holds);
    assert_eq!(
        read.with_claim_failures().unwrap().len(),
        1,
        "by-sign is right here"
    );
    let mut changed = read.clone();
    changed.failure.as_mut().unwrap().answer = Some(0);
    let changed = Found::<Segments>::parse(&changed.to_json()).unwrap();
    assert_ne!(replay(&changed).unwrap(), Replay::Holds);
    // Shrunk through the default numbers (the ray's): still failing, the original kept.
    let (shrunk, _) = tetwalk::engine::shrink::shrink_found(&read, 1000)
        .unwrap()
        .unwrap();
    assert_eq!(shrunk.original, Some(read.case));
    let shrunk = Found::<Segments>::parse(&shrunk.to_json()).unwrap();
    assert_eq!(replay(&shrunk).unwrap(), Replay::Holds);
}

/// The conformance kit judges a method of the toy family: every stress row, then its property
/// campaign; the flushing one is caught with a case that fails again.
#[test]
fn a_toy_family_gets_the_kit() {
    let s = Settings {
        cases: 300,
        properties: 300,
        ..Settings::default()
    };
    let passed = kit::run::check::<Segments>(&METHODS[0], &s).unwrap();
    assert_eq!(passed.groups.len(), 3, "two rows and the property campaign");
    let failed = kit::run::check::<Segments>(&METHODS[1], &s).unwrap_err();
    assert_eq!(failed.family, "segment");
    assert_eq!(failed.group, "stress row subnormal");
    assert!(failed.reproduced, "{failed}");
}
