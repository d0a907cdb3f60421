//! Count tables: per method, wrong rays per image by kind, the work per image and speed, then the
//! totals (seed 000 Table 4's measure, for every family that counts a scene).

use super::relabel_spread;
use crate::engine::count::CountReport;
use crate::family::count::{Counted, Counts};

/// How a counted family's count reads.
pub trait CountFormats: Counted {
    fn count_table(r: &CountReport<Self>) -> String;
}

impl<F: CountFormats> CountReport<F> {
    /// The count's table, as its family reads it ([`CountFormats::count_table`]).
    pub(crate) fn table(&self) -> String {
        F::count_table(self)
    }
}

/// A count's last line: each method's wrong rays over all the rays counted.
pub(crate) fn totals<F: Counted>(r: &CountReport<F>) -> String {
    let each: Vec<String> = r
        .methods
        .iter()
        .map(|m| match m.left_out {
            None => format!("{} {}", m.method, m.counts.wrong_total()),
            Some(l) => format!(
                "{} {} of the {} judged step by step ({} left out: a step its contract leaves no case)",
                m.method,
                m.counts.wrong_total(),
                r.rays - l,
                l
            ),
        })
        .collect();
    let contract = (r.settings.count.answerer.as_ref())
        .and_then(|a| a.contract.as_ref())
        .map_or(String::new(), |k| {
            format!("each step asked under the contract: {k}\n")
        });
    format!(
        "\n{contract}totals over {} rays: {}\n",
        r.rays,
        each.join(", ")
    )
}

/// The wrong rays under the 12 relabellings, per method that has them.
pub(crate) fn relabellings<F: Counted>(r: &CountReport<F>) -> String {
    let mut out = String::new();
    for m in &r.methods {
        if let Some(w) = &m.relabelled {
            out += &format!("| {} | {} |\n", m.method, relabel_spread(w));
        }
    }
    if out.is_empty() {
        return out;
    }
    "\nwrong rays under the 12 orientation-preserving relabellings of the tetrahedra\n\n| method | own labelling | min | median | max |\n|---|---|---|---|---|\n".to_string() + &out
}

/// On a GPU, what each row's answers moved between the CPU and the GPU, per ray, its dispatches, the
/// times the CPU waited for the GPU, the answers sent back to be judged, and the kernels' share of
/// its wall time.
pub(crate) fn transfers<F: Counted>(r: &CountReport<F>) -> String {
    let mut out = String::new();
    for m in &r.methods {
        if let Some(t) = &m.transfer {
            let share = t
                .kernel_share
                .map_or("-".into(), |k| format!("{:.1}%", 100.0 * k));
            out += &format!(
                "| {} | {:.1} | {:.1} | {} | {} | {} | {share} |\n",
                m.method,
                t.bytes_written_per_ray,
                t.bytes_read_per_ray,
                t.total.dispatches,
                t.total.waits,
                t.total.sent_back
            );
        }
    }
    if out.is_empty() {
        return out;
    }
    "\nbetween the CPU and the GPU, per ray counted\n\n| method | bytes written | bytes read back | dispatches | waits | sent back | kernels' share of the wall time |\n|---|---|---|---|---|---|---|\n".to_string() + &out
}

/// `(audited against … on N rays, all agreeing)`, or nothing when no ray was audited.
pub(crate) fn audited<F: Counted>(r: &CountReport<F>, against: &str) -> String {
    if r.audited > 0 {
        format!(
            " (audited against {against} on {} rays, all agreeing)",
            r.audited
        )
    } else {
        String::new()
    }
}
