//! The parsed and validated declaration: what every later stage (analysis, jets emission,
//! symbolic lowering) works from.

use proc_macro2::{Ident, Span};

/// How the derivatives of L are computed in the generated impl.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Run-time forward-mode jets (`ElJet`): the default `Lagrangian` provided methods.
    Jets,
    /// Compile-time symbolic jets: straight-line code for M and the right-hand side.
    Symbolic,
}

/// Options from the attribute: `#[lagrangian(mode = "jets")]`, `#[lagrangian(lanes)]`.
#[derive(Clone, Debug)]
pub struct Options {
    /// The derivation mode.
    pub mode: Mode,
    /// Whether `mode` was given explicitly (span of the value if so).
    pub mode_span: Option<Span>,
    /// `lanes`: the lanes code whatever the system's size (span of the argument if given).
    pub lanes: Option<Span>,
}

/// The kind of a coordinate parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CoordKind {
    /// `(x, x_dot): Coord`: one generalized coordinate, bound as `Scalar`.
    Scalar,
    /// `(r, r_dot): Coord3`: three coordinates, bound as `Vector3<Scalar>`.
    Vector3,
    /// `(q, q_dot): Coords<K>`: K coordinates, bound as `[Scalar; K]` (K ≥ 1, a literal).
    Array(usize),
}

impl CoordKind {
    /// The type as the user writes it (`Coord`, `Coord3`, `Coords<6>`).
    pub fn type_name(self) -> String {
        match self {
            CoordKind::Scalar => "Coord".to_owned(),
            CoordKind::Vector3 => "Coord3".to_owned(),
            CoordKind::Array(k) => format!("Coords<{k}>"),
        }
    }
}

/// One coordinate parameter of `fn lagrangian`.
#[derive(Clone, Debug)]
pub struct CoordParam {
    /// Scalar or Vector3.
    pub kind: CoordKind,
    /// The coordinate binding (`theta`, `r`).
    pub name: Ident,
    /// The velocity binding (`theta_dot`, `r_dot`).
    pub dot: Ident,
    /// Index of this parameter's first slot in q (slots are numbered in declaration order).
    pub first_index: usize,
}

impl CoordParam {
    /// How many slots of q this parameter occupies (1, 3 or K).
    pub fn width(&self) -> usize {
        match self.kind {
            CoordKind::Scalar => 1,
            CoordKind::Vector3 => 3,
            CoordKind::Array(k) => k,
        }
    }
    /// The COORDINATES names of this parameter's slots: `theta`, or `r.x`, `r.y`, `r.z`, or
    /// `q[0]` … `q[K-1]`.
    pub fn slot_names(&self) -> Vec<String> {
        // `(_x, x_dot)` marks a coordinate L does not read (rustc's unused-variable
        // convention): its name is `x`, not `_x`, in COORDINATES, the equations and the CSV.
        let raw = unraw(&self.name);
        let base = match raw.strip_prefix('_') {
            Some(rest) if !rest.is_empty() => rest.to_string(),
            _ => raw,
        };
        match self.kind {
            CoordKind::Scalar => vec![base],
            CoordKind::Vector3 => ["x", "y", "z"]
                .iter()
                .map(|c| format!("{base}.{c}"))
                .collect(),
            CoordKind::Array(k) => (0..k).map(|i| format!("{base}[{i}]")).collect(),
        }
    }
}

/// Which of the optional functions next to `fn lagrangian` a [`Func`] is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FuncKind {
    /// `fn dissipation(&self, ...) -> Scalar`: the Rayleigh dissipation function D.
    Dissipation,
    /// `fn forces(&self, ...) -> [Scalar; N]`: the generalized forces Q.
    Forces,
    /// `fn constraints(&self, ...) -> [Scalar; K]`: the holonomic constraints g(q, t) = 0.
    Constraints,
    /// `fn contacts(&self, ...) -> [Contact; K]`: the unilateral contacts g(q, t) ≥ 0.
    Contacts,
    /// `fn velocity_constraints(&self, ...) -> [Scalar; K]`: the nonholonomic constraints
    /// A(q, t) q̇ + b(q, t) = 0.
    VelocityConstraints,
    /// `fn scene(&self, ...) -> Scene`: what the system looks like at a state, from the
    /// positions (and the time).
    Scene,
}

impl FuncKind {
    /// The name the user writes (`dissipation`, `forces`).
    pub fn user_name(self) -> &'static str {
        match self {
            FuncKind::Dissipation => "dissipation",
            FuncKind::Forces => "forces",
            FuncKind::Constraints => "constraints",
            FuncKind::Contacts => "contacts",
            FuncKind::VelocityConstraints => "velocity_constraints",
            FuncKind::Scene => "scene",
        }
    }
    /// The trait method it becomes (of `Lagrangian`, or of `Holonomic` for constraints).
    pub fn trait_method(self) -> &'static str {
        match self {
            FuncKind::Dissipation => "dissipation",
            FuncKind::Forces => "generalized_forces",
            FuncKind::Constraints => "constraints",
            FuncKind::Contacts => "contacts",
            FuncKind::VelocityConstraints => "velocity_constraints",
            FuncKind::Scene => "scene",
        }
    }
    /// Whether its body depends on the positions (and the time) only: `fn constraints`,
    /// `fn contacts` and `fn scene`.
    pub fn positions_only(self) -> bool {
        matches!(
            self,
            FuncKind::Constraints | FuncKind::Contacts | FuncKind::Scene
        )
    }
}

/// `fn dissipation`, `fn forces` or `fn constraints` after validation: the same coordinates as
/// `fn lagrangian` (bound under names of its own, or not at all), its own optional time.
#[derive(Clone)]
pub struct Func {
    /// Dissipation, forces or constraints.
    pub kind: FuncKind,
    /// Attributes on the function (doc comments, `#[allow(...)]`), kept on the generated method.
    pub fn_attrs: Vec<syn::Attribute>,
    /// The function's identifier as written (for spans).
    pub fn_ident: Ident,
    /// The span of the return type.
    pub ret_span: Span,
    /// One entry per coordinate parameter of `fn lagrangian`, in its order: the coordinate and
    /// velocity bindings (`None` for `_`).
    pub bindings: Vec<(Option<Ident>, Option<Ident>)>,
    /// The `t: Time` parameter, if any.
    pub time: Option<Ident>,
    /// The body as written.
    pub body: syn::Block,
    /// The `self` token of the receiver as written.
    pub self_token: syn::Token![self],
    /// K, the number of constraints (`fn constraints` only; 0 for the others).
    pub k: usize,
    /// `fn velocity_constraints`: some entry has a velocity-free term b(q, t) (then the
    /// constraint forces can do work, as a moving constraint's do).
    pub affine: bool,
}

/// `fn lagrangian` after parsing and validation.
#[derive(Clone)]
pub struct Decl {
    /// The impl block with `fn lagrangian`, `fn dissipation`, `fn forces` and `fn constraints`
    /// removed; everything
    /// else is emitted as written.
    pub rest: syn::ItemImpl,
    /// Attributes on `fn lagrangian` (doc comments, `#[allow(...)]`, ...), kept on the generated fn.
    pub fn_attrs: Vec<syn::Attribute>,
    /// The `lagrangian` identifier (for spans).
    pub fn_ident: Ident,
    /// The `Scalar` return type token span.
    pub ret_span: Span,
    /// Coordinate parameters in declaration order.
    pub coords: Vec<CoordParam>,
    /// The `t: Time` parameter, if any.
    pub time: Option<Ident>,
    /// The body as written.
    pub body: syn::Block,
    /// The `self` token of the receiver as written (its span makes `self` in the body resolve,
    /// also when the impl block comes out of a `macro_rules!`).
    pub self_token: syn::Token![self],
    /// Attribute options.
    pub options: Options,
    /// `fn dissipation`, if the impl block has one.
    pub dissipation: Option<Func>,
    /// `fn forces`, if the impl block has one.
    pub forces: Option<Func>,
    /// `fn constraints`, if the impl block has one (emitted as `impl Holonomic<N, K>`; not part
    /// of the equations of `Lagrangian`, so not among [`Decl::funcs`]).
    pub constraints: Option<Func>,
    /// `fn contacts`, if the impl block has one (emitted as `impl Unilateral<N, K>`).
    pub contacts: Option<Func>,
    /// `fn velocity_constraints`, if the impl block has one (emitted as
    /// `impl Nonholonomic<N, K>`, its rows folded into `impl Holonomic`).
    pub velocity_constraints: Option<Func>,
    /// `fn scene`, if the impl block has one (emitted as `impl Visual<N>`, its body evaluated
    /// in `f64` at the states of a run).
    pub scene: Option<Func>,
}

impl Decl {
    /// Number of generalized coordinates N.
    pub fn n(&self) -> usize {
        self.coords.iter().map(CoordParam::width).sum()
    }
    /// `fn dissipation` and `fn forces`, those present.
    pub fn funcs(&self) -> impl Iterator<Item = &Func> {
        self.dissipation.iter().chain(&self.forces)
    }
    /// COORDINATES, in declaration order.
    pub fn coordinate_names(&self) -> Vec<String> {
        self.coords
            .iter()
            .flat_map(CoordParam::slot_names)
            .collect()
    }
}

/// An identifier's name without the `r#` prefix.
pub fn unraw(ident: &Ident) -> String {
    let s = ident.to_string();
    s.strip_prefix("r#").map(str::to_owned).unwrap_or(s)
}

/// Whether tokens mention the identifier `Scalar`.
pub fn mentions_scalar(ts: proc_macro2::TokenStream) -> bool {
    ts.into_iter().any(|tt| match tt {
        proc_macro2::TokenTree::Ident(i) => i == "Scalar",
        proc_macro2::TokenTree::Group(g) => mentions_scalar(g.stream()),
        _ => false,
    })
}

/// Whether a function is written with the number type `Scalar` in its signature (and has no
/// generics of its own): a helper method of the impl block (with `self`), or a `fn` item in a
/// body. Both modes make it generic over the number type; the symbolic mode inlines it.
pub fn uses_scalar(sig: &syn::Signature) -> bool {
    sig.generics.params.is_empty()
        && (mentions_scalar(quote::ToTokens::to_token_stream(&sig.inputs))
            || mentions_scalar(quote::ToTokens::to_token_stream(&sig.output)))
}

/// Whether a method of the impl block is a helper: it takes `self` and is written with `Scalar`
/// ([`uses_scalar`]), like `fn kinetic(&self, v: Scalar) -> Scalar`.
pub fn is_helper(f: &syn::ImplItemFn) -> bool {
    f.sig.receiver().is_some() && uses_scalar(&f.sig)
}
