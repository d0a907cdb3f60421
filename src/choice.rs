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

/// The arithmetic models, written once (in the spirit of CGAL's interface macros): `$then!` is
/// called with `[ARGS]` (what follows `$then,` here) and one line per model — its [`Model`] variant, its CPU backend's [`BackendKind`] variant
/// and name, the `crate::methods::Arith` types that compute it (portable, a twin on an instruction
/// the processor may have, rounding alike, and the twin the exit-face tables use), its words in
/// reports and the [`Instruction`] its twin is compiled for. [`Model`], the CPU backends, the registry's per-model tables and every list of CPU
/// backends expand from it; a new model is a line here and its `Arith` types.
#[doc(hidden)]
#[macro_export]
macro_rules! arithmetic_models {
    ($then:ident $(, $($args:tt)*)?) => {
        $then! {
            [$($($args)*)?]
            /// Each operation rounded once, as written, with gradual underflow (`cpu`).
            Plain, Cpu => "cpu", (Plain, Plain, PlainAvx2), { "plain f32", Avx2 };
            /// `a·b + c` fused into one rounding where a GPU compiler may contract it (`cpu-fma`).
            Fused, CpuFma => "cpu-fma", (Fused, FusedFma, FusedFma), { "fma", Fma };
            /// As written, with subnormal inputs read as zero and subnormal results flushed (`cpu-ftz`).
            Flushed, CpuFtz => "cpu-ftz", (Flushed, Flushed, Flushed),
                { "f32, subnormals flushed to zero", Avx2 };
            /// Fused and flushed at once, as an NVIDIA GPU computes a compute shader (an H200 on
            /// Vulkan fuses multiply-adds and flushes subnormals, `corpora/results/h200/`) (`cpu-gpu`).
            FusedFlushed, CpuGpu => "cpu-gpu", (FusedFlushed, FusedFlushedFma, FusedFlushedFma),
                { "fma, subnormals flushed to zero", Fma };
        }
    };
}

/// The x86-64 instruction set a model's faster twin is compiled for (used where the processor has it).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Instruction {
    /// AVX2: the same IEEE operations with three-operand encodings, eight lanes in a register.
    Avx2,
    /// FMA3: the fused multiply-add in one instruction (else `f32::mul_add`, a library call).
    Fma,
}

/// [`Model`] and [`BackendKind`] from [`arithmetic_models!`].
macro_rules! model_and_backends {
    ([] $($(#[$doc:meta])* $model:ident, $backend:ident => $name:literal, ($($arith:ident),*),
        { $words:literal, $instruction:ident };)*) => {
        /// The arithmetic models a CPU backend computes in, each a `crate::methods::Arith`
        /// ([`arithmetic_models!`]).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
        pub enum Model {
            $($(#[$doc])* $model,)*
        }

        impl Model {
            /// How many models there are.
            pub const COUNT: usize = [$(stringify!($model)),*].len();
            /// Every model, in the order reports list them.
            pub const ALL: [Model; Model::COUNT] = [$(Model::$model),*];

            /// The CPU backend that computes in it.
            pub const fn backend(self) -> BackendKind {
                match self {
                    $(Model::$model => BackendKind::$backend,)*
                }
            }

            /// The instruction set its faster twin is compiled for.
            pub const fn instruction(self) -> Instruction {
                match self {
                    $(Model::$model => Instruction::$instruction,)*
                }
            }

            /// What it is, in a few words (`walk`'s heading).
            pub const fn words(self) -> &'static str {
                match self {
                    $(Model::$model => $words,)*
                }
            }
        }

        /// Which backend: the one spelling used by every command (`--backend`), found cases and
        /// reports. One CPU backend per arithmetic model ([`arithmetic_models!`]), a GPU, and a
        /// user's program.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
        pub enum BackendKind {
            $(
                #[doc = concat!("The CPU computing in [`Model::", stringify!($model), "`].")]
                #[serde(rename = $name)]
                $backend,
            )*
            /// A GPU through wgpu (`WGPU_BACKEND`, `WGPU_ADAPTER_NAME`).
            #[serde(rename = "gpu")]
            Gpu,
            /// A user's program outside tetwalk (`--answerer`): where its found cases were found;
            /// nothing tetwalk opens.
            #[serde(rename = "outside")]
            Outside,
        }

        crate::choice!(BackendKind { $($backend => $name,)* Gpu => "gpu", Outside => "outside" });

        impl BackendKind {
            /// The arithmetic model of a CPU backend (none for a GPU, whose compiler and driver
            /// choose, or a user's program).
            pub fn model(self) -> Option<Model> {
                match self {
                    $(BackendKind::$backend => Some(Model::$model),)*
                    BackendKind::Gpu | BackendKind::Outside => None,
                }
            }
        }
    };
}

arithmetic_models!(model_and_backends);

impl BackendKind {
    /// Whether it computes f32 as written: the plain CPU, and a GPU (whatever its compiler makes of the
    /// WGSL); not with products fused or subnormals flushed.
    pub(crate) fn as_written(self) -> bool {
        self == Model::Plain.backend() || self == BackendKind::Gpu
    }

    /// The backends tetwalk opens, `a|b|…` (for messages).
    pub(crate) fn names() -> String {
        let opened = BackendKind::ALL
            .iter()
            .filter(|k| **k != BackendKind::Outside);
        opened.map(|k| k.name()).collect::<Vec<_>>().join("|")
    }
}

/// Where methods ran: a backend's kind, and for a GPU its adapter and driver. Reports write it as
/// a CPU backend's name or `gpu: ADAPTER (…, driver …)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ran {
    pub(crate) kind: BackendKind,
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
                "'{text}' is not one of {} (gpu: ADAPTER)",
                BackendKind::names()
            ))
        })?;
        Ok(Ran { kind, adapter })
    }
}

/// What crossed between the CPU and a GPU, summed: bytes written to it (uploads, uniforms), bytes
/// read back (outputs, timestamps), dispatches, the times the CPU waited for the GPU (each buffer
/// mapped), the answers it sent back to be judged on the CPU where it compared them, and their
/// kernel time where the adapter measures it.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Traffic {
    #[serde(rename = "bytes_written")]
    pub(crate) written: u64,
    #[serde(rename = "bytes_read")]
    pub(crate) read: u64,
    pub dispatches: u64,
    #[serde(default)]
    pub waits: u64,
    #[serde(default)]
    pub sent_back: u64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(crate) kernel_seconds: Option<f64>,
}

impl Traffic {
    /// Both summed (two GPUs', or one's over two spans).
    pub(crate) fn plus(self, o: &Traffic) -> Traffic {
        Traffic {
            written: self.written + o.written,
            read: self.read + o.read,
            dispatches: self.dispatches + o.dispatches,
            waits: self.waits + o.waits,
            sent_back: self.sent_back + o.sent_back,
            kernel_seconds: self
                .kernel_seconds
                .zip(o.kernel_seconds)
                .map(|(a, b)| a + b),
        }
    }

    /// What crossed since `before` (an earlier reading of the same GPU).
    pub(crate) fn since(self, before: Traffic) -> Traffic {
        Traffic {
            written: self.written - before.written,
            read: self.read - before.read,
            dispatches: self.dispatches - before.dispatches,
            waits: self.waits - before.waits,
            sent_back: self.sent_back - before.sent_back,
            kernel_seconds: self
                .kernel_seconds
                .zip(before.kernel_seconds)
                .map(|(a, b)| a - b),
        }
    }
}
