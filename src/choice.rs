//! Closed sets of named values (mesh kinds, shapes, layouts, stress rows, arithmetic models, backends):
//! one name per value, used by the command line, the case format and reports alike.

/// A closed set of named values.
pub trait Choice: Copy + Sized + Send + Sync + 'static {
    /// Every value, in the order help text and reports list them.
    const ALL: &'static [Self];
    /// The value's one name.
    fn name(self) -> &'static str;
    /// The value of a name, if it is one.
    fn from_name(s: &str) -> Option<Self> {
        Self::ALL.iter().copied().find(|v| v.name() == s)
    }
}

/// Implement `Choice` for a fieldless enum from `Variant => "name"` pairs.
#[doc(hidden)]
#[macro_export]
macro_rules! choice {
    ($t:ty { $($v:ident => $n:literal),* $(,)? }) => {
        impl $crate::choice::Choice for $t {
            const ALL: &'static [Self] = &[$(<$t>::$v),*];
            fn name(self) -> &'static str {
                match self { $(<$t>::$v => $n),* }
            }
        }
    };
}

/// The arithmetic models a CPU backend computes in, each a `crate::methods::Arith`: as written,
/// products fused into multiply-adds, subnormals flushed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Model {
    /// Each operation rounded once, as written, with gradual underflow (`cpu`).
    Plain,
    /// `a·b + c` fused into one rounding where a GPU compiler may contract it (`cpu-fma`).
    Fused,
    /// As written, with subnormal inputs read as zero and subnormal results flushed (`cpu-ftz`).
    Flushed,
}

impl Model {
    /// Every model, in the order reports list them.
    pub const ALL: [Model; 3] = [Model::Plain, Model::Fused, Model::Flushed];
}

/// Which backend: the one spelling used by every command (`--backend`), found cases and reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BackendKind {
    /// The CPU, every product and sum rounded as written.
    Cpu,
    /// The CPU as a GPU compiler may compile the method: `a·b + c` contracted to fused multiply-adds.
    CpuFma,
    /// The CPU as a GPU may compute: subnormal inputs read as zero, subnormal results flushed to zero.
    CpuFtz,
    /// A GPU through wgpu (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME`).
    Gpu,
    /// A user's program outside tetwalk (`--answerer`): where its found cases were found; nothing
    /// tetwalk opens.
    Outside,
}

crate::choice!(BackendKind { Cpu => "cpu", CpuFma => "cpu-fma", CpuFtz => "cpu-ftz", Gpu => "gpu", Outside => "outside" });

impl BackendKind {
    /// Whether it computes f32 as written: the plain CPU, and a GPU (whatever its compiler makes of the
    /// WGSL); not with products fused or subnormals flushed.
    pub fn as_written(self) -> bool {
        matches!(self, BackendKind::Cpu | BackendKind::Gpu)
    }

    /// The arithmetic model of a CPU backend (none for a GPU, whose compiler and driver choose).
    pub fn model(self) -> Option<Model> {
        match self {
            BackendKind::Cpu => Some(Model::Plain),
            BackendKind::CpuFma => Some(Model::Fused),
            BackendKind::CpuFtz => Some(Model::Flushed),
            BackendKind::Gpu | BackendKind::Outside => None,
        }
    }
}

/// Where methods ran: a backend's kind, and for a GPU its adapter and driver. Reports write it as
/// `cpu`, `cpu-fma`, `cpu-ftz` or `gpu: ADAPTER (…, driver …)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ran {
    pub kind: BackendKind,
    pub adapter: Option<String>,
}

impl std::fmt::Display for Ran {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match &self.adapter {
            Some(a) => write!(f, "{}: {a}", self.kind.name()),
            None => f.write_str(self.kind.name()),
        }
    }
}

impl serde::Serialize for Ran {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

impl<'de> serde::Deserialize<'de> for Ran {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let text = String::deserialize(d)?;
        let (kind, adapter) = match text.split_once(": ") {
            Some((k, a)) => (k, Some(a.to_string())),
            None => (text.as_str(), None),
        };
        let kind = BackendKind::from_name(kind).ok_or_else(|| {
            serde::de::Error::custom(format!(
                "'{text}' is not cpu, cpu-fma, cpu-ftz or gpu: ADAPTER"
            ))
        })?;
        Ok(Ran { kind, adapter })
    }
}
