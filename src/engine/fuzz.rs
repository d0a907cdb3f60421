//! The fuzz targets' policy, for every family: which methods a run holds to what (`TETWALK_FUZZ_METHOD`),
//! on which backends (`TETWALK_FUZZ_BACKEND`), and what it finds on one decoded case. Each cargo-fuzz
//! target is [`target`] for its family.

use super::found::{Found, FoundError, Hold, check, cpu_backends};
use crate::backend::{Backend, BackendKind};
use crate::family::{self, Family};
use crate::registry::Named;
use crate::tet::Ray;
use glam::Vec3;

/// The variable naming a user's WGSL exit-face function to fuzz (`--wgsl`'s file, on the GPU).
pub(crate) const FUZZ_WGSL: &str = "TETWALK_FUZZ_WGSL";

/// What `TETWALK_FUZZ_METHOD` says, or the default compiled in with `TETWALK_FUZZ_DEFAULT`
/// (ClusterFuzzLite's build uses `ours`), else `robust`.
fn choice() -> String {
    let default = option_env!("TETWALK_FUZZ_DEFAULT").unwrap_or("robust");
    std::env::var("TETWALK_FUZZ_METHOD").unwrap_or_else(|_| default.into())
}

/// The methods of family `F` a fuzz run holds, and to what: with `TETWALK_FUZZ_WGSL=FILE` (for a family
/// with a user's WGSL method) that method, to every answer; else from `TETWALK_FUZZ_METHOD`: `robust`,
/// every method that makes a claim, to its claim; `ours`, those tetwalk vouches for
/// ([`crate::registry::Info::ours`]), to their claims; or one method's name, to every answer (with
/// the family's reference beside it).
pub fn held<F: Family>() -> Result<Vec<(&'static F::Method, Hold)>, FoundError> {
    let reference = family::reference::<F>().map(|m| (m, Hold::Every));
    if std::env::var_os(FUZZ_WGSL).is_some()
        && let Some(user) = F::user_wgsl()
    {
        return Ok(reference.into_iter().chain([(user, Hold::Every)]).collect());
    }
    let claiming = |keep: fn(&crate::registry::Info) -> bool| {
        F::methods()
            .iter()
            .filter(|m| m.info().claim.is_some() && keep(m.info()))
            .map(|m| (m, Hold::Claim))
            .collect()
    };
    Ok(match choice().as_str() {
        "robust" => claiming(|_| true),
        "ours" => claiming(|i| i.ours),
        name => {
            let m = family::by_name::<F>(name).map_err(FoundError::FuzzMethod)?;
            reference
                .filter(|(r, _)| r.name() != m.name())
                .into_iter()
                .chain([(m, Hold::Every)])
                .collect()
        }
    })
}

/// The GPU a fuzz run with `TETWALK_FUZZ_BACKEND=gpu` holds the methods to, opened once.
static FUZZ_GPU: std::sync::OnceLock<Result<Backend, String>> = std::sync::OnceLock::new();

/// The backends a fuzz run holds the methods to, from `TETWALK_FUZZ_BACKEND`: `cpu` (the default: the
/// CPU plain, fused and flushed) or `gpu` (the adapter `WGPU_ADAPTER_NAME` names, or the default one;
/// opened with the `TETWALK_FUZZ_WGSL` function spliced in, when set).
pub(crate) fn backends() -> Result<Vec<&'static Backend>, FoundError> {
    match std::env::var("TETWALK_FUZZ_BACKEND").as_deref() {
        Err(_) | Ok("cpu") if std::env::var_os(FUZZ_WGSL).is_some() => {
            Err(FoundError::FuzzBackend(format!(
                "{FUZZ_WGSL} fuzzes a WGSL function: set TETWALK_FUZZ_BACKEND=gpu"
            )))
        }
        Err(_) | Ok("cpu") => Ok(cpu_backends()),
        Ok("gpu") => FUZZ_GPU
            .get_or_init(|| match std::env::var(FUZZ_WGSL) {
                Ok(path) => std::fs::read_to_string(&path)
                    .map_err(|e| format!("{FUZZ_WGSL}={path}: {e}"))
                    .and_then(|src| Backend::gpu_with_user(&path, &src).map_err(|e| e.to_string())),
                Err(_) => Backend::open(BackendKind::Gpu).map_err(|e| e.to_string()),
            })
            .as_ref()
            .map(|g| vec![g])
            .map_err(|why| FoundError::FuzzBackend(why.clone())),
        Ok(other) => Err(FoundError::FuzzBackend(format!(
            "'{other}' is not cpu or gpu"
        ))),
    }
}

/// What a fuzz run finds on one decoded case, on the methods and backends its environment names
/// ([`held`], [`backends`]): on the CPU, the case itself; on a GPU, the case and its [`neighbourhood`]
/// in one batch (one dispatch per method), so that each input does a dispatch's worth of work. A method
/// held to a claim made only of f32 as written is held on the plain CPU and the GPU alone. The exact
/// judge runs on the CPU.
pub(crate) fn find<F: Family>(case: &F::Case) -> Result<Option<Found<F>>, FoundError> {
    let backends = backends()?;
    let cases = if backends.iter().any(|b| b.ran().kind == BackendKind::Gpu) {
        neighbourhood::<F>(case)
    } else {
        vec![*case]
    };
    let mut found = None;
    for (m, hold) in held::<F>()? {
        let written_only =
            hold == Hold::Claim && m.info().claim.is_some_and(|c| c.as_written_only());
        let on: Vec<&Backend> = backends
            .iter()
            .copied()
            .filter(|b| !written_only || b.ran().kind.as_written())
            .collect();
        // A case the oracle cannot judge (a walk's origin outside its mesh) finds nothing.
        found = match check::<F>(&cases, &[(m, hold)], &on) {
            Err(FoundError::Case(_)) => return Ok(None),
            other => other?,
        };
        if found.is_some() {
            break;
        }
    }
    Ok(found.map(|(i, f)| Found::of(cases[i], f)))
}

/// What a held method fails on an artifact's case ([`find`]): a found case's line read back (`json`),
/// or else the fuzz target's decoding of a crash file's bytes.
pub(crate) fn finding<F: Family>(bytes: &[u8], json: bool) -> Result<Option<Found<F>>, FoundError> {
    let case = if json {
        Some(Found::<F>::parse(String::from_utf8_lossy(bytes).trim())?.case)
    } else {
        F::arbitrary(&mut arbitrary::Unstructured::new(bytes))
    };
    case.map_or(Ok(None), |c| find::<F>(&c))
}

/// A fuzz target's check of one decoded case ([`find`]); a bad environment stops the run.
pub(crate) fn check_one<F: Family>(case: &F::Case) -> Option<Found<F>> {
    find::<F>(case).unwrap_or_else(|e| match e {
        FoundError::FuzzMethod(_) | FoundError::FuzzBackend(_) => panic!("{e}"),
        _ => None,
    })
}

/// The body of family `F`'s cargo-fuzz target: decode a case from the fuzzer's bytes
/// ([`Family::arbitrary`]) and fail, printing the found case, where a held method answers it wrongly.
pub fn target<F: Family>(data: &[u8]) {
    let mut u = arbitrary::Unstructured::new(data);
    if let Some(case) = F::arbitrary(&mut u)
        && let Some(found) = check_one::<F>(&case)
    {
        panic!("{}", found.to_json());
    }
}

/// Ulps by which [`neighbourhood`] moves each component.
const NEIGHBOUR_ULPS: [i32; 3] = [-1, 0, 1];

/// The case and its neighbours a few ulps away: its ray's direction, then its origin, moved by -1, 0
/// or +1 ulp in each component (53 cases, the case itself first).
pub fn neighbourhood<F: Family>(case: &F::Case) -> Vec<F::Case> {
    let ray = F::ray(case);
    let moved = |p: Vec3, k: usize| {
        let d = [k % 3, k / 3 % 3, k / 9].map(|i| NEIGHBOUR_ULPS[i]);
        Vec3::new(
            crate::scenes::tets::ulps(p.x, d[0]),
            crate::scenes::tets::ulps(p.y, d[1]),
            crate::scenes::tets::ulps(p.z, d[2]),
        )
    };
    let mut out = vec![*case];
    for k in (0..27).filter(|&k| k != 13) {
        out.push(F::with_ray(
            case,
            Ray {
                org: ray.org,
                dir: moved(ray.dir, k),
            },
        ));
    }
    for k in (0..27).filter(|&k| k != 13) {
        out.push(F::with_ray(
            case,
            Ray {
                org: moved(ray.org, k),
                dir: ray.dir,
            },
        ));
    }
    out.retain(|c| {
        let r = F::ray(c);
        r.dir != Vec3::ZERO && r.dir.is_finite() && r.org.is_finite()
    });
    out
}
