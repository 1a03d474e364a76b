//! The Euler–Lagrange equations for people: each equation is expanded into a sum of monomials
//! over atoms (parameters, coordinates, velocities, accelerations, time, and elementary
//! functions of sub-expressions), like terms are collected, terms that share the same
//! state-dependent part are grouped under a parameter coefficient (`(I∥ − I⊥) φ̇² sin(θ) cos(θ)`),
//! and the acceleration terms are put on the left: `Σₖ Mᵢₖ q̈ₖ = fᵢ`.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

use super::dag::{Dag, Fun, Id, Node};
use super::derive::Derivation;
use super::poly::{self, mono_mul, PRINTING};
use crate::model::{unraw, CoordKind, Decl};

/// The equations as text.
pub struct Equations {
    pub unicode: String,
    pub latex: String,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
enum Atom {
    Param(u32, u8),
    A(u32),
    V(u32),
    Q(u32),
    T,
    Fun(Fun, Id),
    Atan2(Id, Id),
    Powf(Id, Id),
    /// `(a if cond else b)` (a `Node::Select`).
    Select(Id),
    /// A sum that could not be expanded (a denominator, a negative power, a too-large product).
    Paren(Id),
    /// `sin(a − b)` or `cos(a − b)` (`Fun::Sin`, `Fun::Cos`), merged by [`pythagoras`] from
    /// products of the sines and cosines of a and b.
    Diff(Fun, Id, Id),
}

impl Atom {
    fn is_param(self) -> bool {
        matches!(self, Atom::Param(..))
    }
}

type Mono = poly::Mono<Atom>;
type Poly = poly::Poly<Atom>;

/// `a + sign·b` (printing keeps every sum: no cap).
fn plus(a: &Poly, b: &Poly, sign: f64) -> Poly {
    a.add(b, sign, &PRINTING).0
}

/// `(a)·(b)` or `(a)/(b)` (`sign` −1) left unexpanded, past the caps. Never `Paren` of the
/// product node itself: that would print the node through itself, without end.
fn unexpanded(a: Id, b: Id, sign: i32) -> Poly {
    let (a, b) = (Atom::Paren(a), Atom::Paren(b));
    let m = match (a.cmp(&b), sign) {
        (std::cmp::Ordering::Equal, 1) => vec![(a, 2)],
        (std::cmp::Ordering::Equal, _) => return Poly::constant(1.0),
        (std::cmp::Ordering::Less, _) => vec![(a, 1), (b, sign)],
        (std::cmp::Ordering::Greater, _) => vec![(b, sign), (a, 1)],
    };
    let mut p = Poly::default();
    p.0.insert(m, 1.0);
    p
}

struct Expander<'a> {
    dag: &'a Dag,
    memo: HashMap<Id, Poly>,
    /// Monomials expanded so far; past [`PRINT_BUDGET`] the printing stops (see `equations`).
    work: usize,
    /// The conditions printed as if they held: a zip's guards that an array field reaches an
    /// element (`Cond::assumed`).
    assumed: Vec<bool>,
}

/// The most monomials the printer expands for one system: a 64-link chain's equations cost
/// 28 s of its build to expand in full; past this the remaining equations say they are too
/// large to print (M, f and the equations themselves are unaffected).
const PRINT_BUDGET: usize = 400_000;

impl Expander<'_> {
    fn over_budget(&self) -> bool {
        self.work > PRINT_BUDGET
    }

    fn poly(&mut self, id: Id) -> Poly {
        if let Some(p) = self.memo.get(&id) {
            return p.clone();
        }
        if self.over_budget() {
            return Poly::atom(Atom::Paren(id), 1);
        }
        // Expand children first, iteratively, to bound the recursion depth.
        // Each node is expanded once: a node reached again by another path before it is done
        // would otherwise be walked once per path (exponential in a chain of shared diamonds).
        let mut order = Vec::new();
        let mut seen = std::collections::HashSet::new();
        let mut stack = vec![(id, false)];
        while let Some((x, done)) = stack.pop() {
            if self.memo.contains_key(&x) {
                continue;
            }
            if done {
                order.push(x);
                continue;
            }
            if !seen.insert(x) {
                continue;
            }
            stack.push((x, true));
            for c in self.expandable_children(x) {
                if !self.memo.contains_key(&c) {
                    stack.push((c, false));
                }
            }
        }
        for x in order {
            if self.over_budget() {
                return Poly::atom(Atom::Paren(id), 1);
            }
            if !self.memo.contains_key(&x) {
                let p = self.one(x);
                self.work += p.0.len();
                self.memo.insert(x, p);
            }
        }
        self.memo.get(&id).cloned().unwrap_or_default()
    }

    fn expandable_children(&self, id: Id) -> Vec<Id> {
        match self.dag.node(id) {
            Node::Select(c, a, _) if self.assumed(c) => vec![a],
            Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => vec![a, b],
            Node::Neg(a) | Node::Powi(a, _) => vec![a],
            _ => Vec::new(),
        }
    }

    fn get(&self, id: Id) -> Poly {
        self.memo.get(&id).cloned().unwrap_or_default()
    }

    fn one(&mut self, id: Id) -> Poly {
        let dag = self.dag;
        match dag.node(id) {
            Node::Const(b) => Poly::constant(f64::from_bits(b)),
            Node::Param(f, c) => Poly::atom(Atom::Param(f, c), 1),
            Node::Q(i) => Poly::atom(Atom::Q(i), 1),
            Node::V(i) => Poly::atom(Atom::V(i), 1),
            Node::T => Poly::atom(Atom::T, 1),
            Node::Add(a, b) => plus(&self.get(a), &self.get(b), 1.0),
            Node::Sub(a, b) => plus(&self.get(a), &self.get(b), -1.0),
            Node::Neg(a) => self.get(a).scale(-1.0),
            Node::Mul(a, b) => self
                .get(a)
                .mul(&self.get(b), &PRINTING)
                .unwrap_or_else(|| unexpanded(a, b, 1)),
            Node::Div(a, b) => {
                let pb = self.get(b);
                let inv = match pb
                    .single()
                    .and_then(|(m, c)| Some((mono_mul(&Vec::new(), m, -1)?, c)))
                {
                    Some((m, c)) => {
                        let mut p = Poly::default();
                        p.0.insert(m, 1.0 / c);
                        p
                    }
                    None => Poly::atom(Atom::Paren(b), -1),
                };
                self.get(a)
                    .mul(&inv, &PRINTING)
                    .unwrap_or_else(|| unexpanded(a, b, -1))
            }
            Node::Powi(a, n) => {
                let pa = self.get(a);
                if let Some((m, c)) = pa.single() {
                    // (an exponent past i32 keeps the power outside: `(x²)^(i32::MIN)`)
                    let m: Option<Mono> = m
                        .iter()
                        .map(|&(x, e)| Some((x, e.checked_mul(n)?)))
                        .collect();
                    if let Some(m) = m {
                        let mut p = Poly::default();
                        p.0.insert(m, c.powi(n));
                        return p;
                    }
                    return Poly::atom(Atom::Paren(a), n);
                }
                if (1..=4).contains(&n) {
                    let mut r = Poly::constant(1.0);
                    for _ in 0..n {
                        match r.mul(&pa, &PRINTING) {
                            Some(x) => r = x,
                            None => return Poly::atom(Atom::Paren(a), n),
                        }
                    }
                    r
                } else {
                    Poly::atom(Atom::Paren(a), n)
                }
            }
            Node::Powf(a, b) => Poly::atom(Atom::Powf(a, b), 1),
            Node::Atan2(a, b) => Poly::atom(Atom::Atan2(a, b), 1),
            Node::Un(f, a) => Poly::atom(Atom::Fun(f, a), 1),
            Node::Select(c, a, _) if self.assumed(c) => self.get(a),
            Node::Select(..) => Poly::atom(Atom::Select(id), 1),
        }
    }

    fn assumed(&self, c: u32) -> bool {
        self.assumed.get(c as usize).copied().unwrap_or(false)
    }
}

/// How a coordinate slot is displayed.
struct SlotName {
    /// Single-symbol base (`θ`, `x`, `r`): dots go over it. Otherwise a multi-letter name.
    base_u: String,
    base_l: String,
    single: bool,
    /// Subscript (`₁`) or component (`.x`), Unicode and LaTeX.
    sub_u: String,
    sub_l: String,
}

const GREEK: &[(&str, &str, &str)] = &[
    ("alpha", "α", "\\alpha"),
    ("beta", "β", "\\beta"),
    ("gamma", "γ", "\\gamma"),
    ("delta", "δ", "\\delta"),
    ("epsilon", "ε", "\\epsilon"),
    ("zeta", "ζ", "\\zeta"),
    ("eta", "η", "\\eta"),
    ("theta", "θ", "\\theta"),
    ("iota", "ι", "\\iota"),
    ("kappa", "κ", "\\kappa"),
    ("lambda", "λ", "\\lambda"),
    ("mu", "μ", "\\mu"),
    ("nu", "ν", "\\nu"),
    ("xi", "ξ", "\\xi"),
    ("pi", "π", "\\pi"),
    ("rho", "ρ", "\\rho"),
    ("sigma", "σ", "\\sigma"),
    ("tau", "τ", "\\tau"),
    ("upsilon", "υ", "\\upsilon"),
    ("phi", "φ", "\\phi"),
    ("chi", "χ", "\\chi"),
    ("psi", "ψ", "\\psi"),
    ("omega", "ω", "\\omega"),
    ("Gamma", "Γ", "\\Gamma"),
    ("Delta", "Δ", "\\Delta"),
    ("Theta", "Θ", "\\Theta"),
    ("Lambda", "Λ", "\\Lambda"),
    ("Phi", "Φ", "\\Phi"),
    ("Psi", "Ψ", "\\Psi"),
    ("Omega", "Ω", "\\Omega"),
];

fn subscript_digits(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '0'..='9' => char::from_u32(0x2080 + (c as u32 - '0' as u32)).unwrap_or(c),
            _ => c,
        })
        .collect()
}

fn superscript(n: i64) -> String {
    let digits = |c: char| match c {
        '0' => '⁰',
        '1' => '¹',
        '2' => '²',
        '3' => '³',
        '4' => '⁴',
        '5' => '⁵',
        '6' => '⁶',
        '7' => '⁷',
        '8' => '⁸',
        '9' => '⁹',
        '-' => '⁻',
        other => other,
    };
    n.to_string().chars().map(digits).collect()
}

/// Splits `theta_1`/`theta1` into (`theta`, `1`) and maps Greek names.
fn symbol(name: &str) -> SlotName {
    let trimmed = name.trim_end_matches(|c: char| c.is_ascii_digit());
    let digits = &name[trimmed.len()..];
    let base = if digits.is_empty() {
        name
    } else {
        trimmed.strip_suffix('_').unwrap_or(trimmed)
    };
    let (bu, bl, single) = match GREEK.iter().find(|(n, _, _)| *n == base) {
        Some((_, u, l)) => ((*u).to_owned(), (*l).to_owned(), true),
        None if base.chars().count() == 1 => (base.to_owned(), base.to_owned(), true),
        None => (base.to_owned(), latex_name(base), false),
    };
    if base.is_empty() {
        return SlotName {
            base_u: name.to_owned(),
            base_l: latex_name(name),
            single: false,
            sub_u: String::new(),
            sub_l: String::new(),
        };
    }
    SlotName {
        base_u: bu,
        base_l: bl,
        single,
        sub_u: subscript_digits(digits),
        sub_l: if digits.is_empty() {
            String::new()
        } else {
            format!("_{{{digits}}}")
        },
    }
}

fn latex_name(s: &str) -> String {
    match s.split_once('_') {
        Some((a, b)) if !a.is_empty() && !b.is_empty() => {
            let head = if a.chars().count() == 1 {
                a.to_owned()
            } else {
                format!("\\mathrm{{{a}}}")
            };
            format!("{head}_{{\\mathrm{{{}}}}}", b.replace('_', "\\_"))
        }
        _ if s.chars().count() == 1 => s.to_owned(),
        _ => format!("\\mathrm{{{}}}", s.replace('_', "\\_")),
    }
}

struct Names {
    slots: Vec<SlotName>,
    params: Vec<(String, String)>,
    /// Conditions of constant `if`s, as written (`self.` dropped).
    conds: Vec<String>,
}

impl Names {
    fn slot(&self, i: u32, dots: usize, latex: bool) -> String {
        let Some(s) = self.slots.get(i as usize) else {
            return "?".to_owned();
        };
        if latex {
            let b = match dots {
                0 => s.base_l.clone(),
                1 => format!("\\dot{{{}}}", s.base_l),
                _ => format!("\\ddot{{{}}}", s.base_l),
            };
            return format!("{b}{}", s.sub_l);
        }
        if s.single {
            let mark = match dots {
                0 => "",
                1 => "\u{307}",
                _ => "\u{308}",
            };
            format!("{}{mark}{}", s.base_u, s.sub_u)
        } else {
            match dots {
                0 => format!("{}{}", s.base_u, s.sub_u),
                1 => format!("d({}{})/dt", s.base_u, s.sub_u),
                _ => format!("d²({}{})/dt²", s.base_u, s.sub_u),
            }
        }
    }
}

fn number(c: f64, latex: bool) -> String {
    if c == c.trunc() && c.abs() < 1e15 {
        return format!("{}", c as i64);
    }
    for den in 2..=16_i64 {
        let num = c * den as f64;
        if num == num.trunc() && num.abs() < 1e6 {
            let num = num as i64;
            return if latex {
                format!("\\frac{{{num}}}{{{den}}}")
            } else {
                format!("{num}/{den}")
            };
        }
    }
    format!("{c}")
}

struct Printer<'a> {
    ex: Expander<'a>,
    names: Names,
    latex: bool,
    /// Rendered sub-expressions (function arguments, parenthesized sums), by node.
    flat: HashMap<Id, String>,
}

/// The nodes an expanded polynomial renders through [`Printer::flat`] (its atoms' arguments).
fn flat_deps(dag: &Dag, p: &Poly, out: &mut Vec<Id>) {
    for m in p.0.keys() {
        for &(a, _) in m {
            match a {
                Atom::Fun(_, x) | Atom::Paren(x) => out.push(x),
                Atom::Atan2(x, y) | Atom::Powf(x, y) | Atom::Diff(_, x, y) => out.extend([x, y]),
                Atom::Select(x) => {
                    if let Node::Select(_, a, b) = dag.node(x) {
                        out.extend([a, b]);
                    }
                }
                Atom::Param(..) | Atom::A(_) | Atom::V(_) | Atom::Q(_) | Atom::T => {}
            }
        }
    }
}

impl Printer<'_> {
    fn fun_name(&self, f: Fun) -> &'static str {
        if self.latex {
            f.row().latex
        } else {
            f.row().unicode
        }
    }

    fn pow(&self, base: String, e: i64) -> String {
        if e == 1 {
            base
        } else if self.latex {
            format!("{base}^{{{e}}}")
        } else {
            format!("{base}{}", superscript(e))
        }
    }

    /// A flat rendering of a sub-expression (a function argument), memoized.
    ///
    /// Nested arguments (`sin(sin(…))`, a chain of parenthesized sums) are rendered innermost
    /// first with an explicit stack, so the call depth stays bounded however deep the body nests.
    fn flat(&mut self, id: Id) -> String {
        if let Some(s) = self.flat.get(&id) {
            return s.clone();
        }
        let mut stack = vec![(id, false)];
        let mut deps = Vec::new();
        // Expanded once each (see `Expander::poly`); in a DAG a node met again while still on
        // the stack is finished before anything that needs it.
        let mut seen = std::collections::HashSet::new();
        while let Some((x, ready)) = stack.pop() {
            if self.flat.contains_key(&x) || (!ready && !seen.insert(x)) {
                continue;
            }
            if self.ex.over_budget() && !self.ex.memo.contains_key(&x) {
                // Past the budget nothing new is expanded: the equation says it is too long.
                self.flat.insert(x, TOO_LONG.to_owned());
                continue;
            }
            let p = self.ex.poly(x);
            if ready {
                // Every argument is in the memo: `sum` → `atom` → `flat` goes one level deep.
                let mut s = self.sum(&p);
                if s.len() > MAX_EQUATION_CHARS {
                    // Past the cap a sub-expression is a marker, so what contains it stays short
                    // (`sin(sin(…))` differentiated prints quadratically long) and the equation
                    // that contains it says it is too long to print.
                    s = TOO_LONG.to_owned();
                }
                self.flat.insert(x, s);
                continue;
            }
            stack.push((x, true));
            deps.clear();
            flat_deps(self.ex.dag, &p, &mut deps);
            for &d in &deps {
                if !self.flat.contains_key(&d) {
                    stack.push((d, false));
                }
            }
        }
        self.flat.get(&id).cloned().unwrap_or_default()
    }

    fn paren(&self, s: String) -> String {
        if self.latex {
            format!("\\left({s}\\right)")
        } else {
            format!("({s})")
        }
    }

    fn atom(&mut self, a: Atom, e: i64) -> String {
        let latex = self.latex;
        match a {
            Atom::Param(f, c) => {
                let (u, l) = self
                    .names
                    .params
                    .get(f as usize)
                    .cloned()
                    .unwrap_or_default();
                let base = if latex { l } else { u };
                let base = match c {
                    1 => format!("{base}.x"),
                    2 => format!("{base}.y"),
                    3 => format!("{base}.z"),
                    _ => base,
                };
                self.pow(base, e)
            }
            Atom::Q(i) => {
                let s = self.names.slot(i, 0, latex);
                self.pow(s, e)
            }
            Atom::V(i) | Atom::A(i) => {
                let dots = if matches!(a, Atom::V(_)) { 1 } else { 2 };
                let s = self.names.slot(i, dots, latex);
                // `d(th₁)/dt²` would read as a second derivative: `(d(th₁)/dt)²`.
                let s = if e != 1 && s.contains("/dt") {
                    format!("({s})")
                } else {
                    s
                };
                self.pow(s, e)
            }
            Atom::T => self.pow("t".to_owned(), e),
            Atom::Fun(f, arg) => {
                let inner = self.flat(arg);
                let name = self.fun_name(f);
                match f {
                    Fun::Abs => {
                        let s = if latex {
                            format!("\\left|{inner}\\right|")
                        } else {
                            format!("|{inner}|")
                        };
                        self.pow(s, e)
                    }
                    Fun::Sqrt if latex => self.pow(format!("\\sqrt{{{inner}}}"), e),
                    Fun::Sqrt => self.pow(format!("√({inner})"), e),
                    _ => {
                        let arg = self.paren(inner);
                        if e == 1 {
                            format!("{name}{arg}")
                        } else if latex {
                            format!("{name}^{{{e}}}{arg}")
                        } else {
                            format!("{name}{}{arg}", superscript(e))
                        }
                    }
                }
            }
            Atom::Diff(f, a, b) => {
                let (a, b) = (self.flat(a), self.flat(b));
                let name = self.fun_name(f);
                let minus = if latex { "-" } else { "−" };
                let arg = self.paren(format!("{a} {minus} {b}"));
                if e == 1 {
                    format!("{name}{arg}")
                } else if latex {
                    format!("{name}^{{{e}}}{arg}")
                } else {
                    format!("{name}{}{arg}", superscript(e))
                }
            }
            Atom::Atan2(y, x) => {
                let (y, x) = (self.flat(y), self.flat(x));
                let s = if latex {
                    format!("\\operatorname{{atan2}}\\left({y}, {x}\\right)")
                } else {
                    format!("atan2({y}, {x})")
                };
                self.pow(s, e)
            }
            Atom::Powf(a, b) => {
                let (a, b) = (self.flat(a), self.flat(b));
                let s = if latex {
                    format!("\\left({a}\\right)^{{{b}}}")
                } else {
                    format!("({a})^({b})")
                };
                self.pow(s, e)
            }
            Atom::Select(x) => {
                let Node::Select(c, a, b) = self.ex.dag.node(x) else {
                    return "?".to_owned();
                };
                let (a, b) = (self.flat(a), self.flat(b));
                let cond = self
                    .names
                    .conds
                    .get(c as usize)
                    .cloned()
                    .unwrap_or_default();
                let s = if latex {
                    let cond: String = cond
                        .chars()
                        .map(|ch| match ch {
                            '_' | '{' | '}' | '&' | '%' | '#' | '$' => format!("\\{ch}"),
                            other => other.to_string(),
                        })
                        .collect();
                    format!(
                        "\\left({a} \\;\\text{{if}}\\; \\texttt{{{cond}}} \\;\\text{{else}}\\; {b}\\right)"
                    )
                } else {
                    format!("({a} if {cond} else {b})")
                };
                self.pow(s, e)
            }
            Atom::Paren(x) => {
                let s = self.flat(x);
                let s = self.paren(s);
                self.pow(s, e)
            }
        }
    }

    /// Renders a product of atoms as "num" or "num/den" (magnitude only, no sign).
    fn product(&mut self, k: f64, atoms: &[(Atom, i32)], coef: Option<String>) -> String {
        let sep = " ";
        let mut num: Vec<String> = Vec::new();
        let mut den: Vec<String> = Vec::new();
        let k = k.abs();
        if k != 1.0 {
            num.push(number(k, self.latex));
        }
        if let Some(c) = coef {
            num.push(c);
        }
        for &(a, e) in atoms {
            if e > 0 {
                let s = self.atom(a, i64::from(e));
                num.push(s);
            } else {
                let s = self.atom(a, -i64::from(e));
                den.push(s);
            }
        }
        // A fraction 1/2 directly before a symbol reads better as a leading factor.
        let n = if num.is_empty() {
            "1".to_owned()
        } else {
            num.join(sep)
        };
        if den.is_empty() {
            n
        } else if self.latex {
            format!("\\frac{{{n}}}{{{}}}", den.join(sep))
        } else if den.len() == 1 {
            format!("{n}/{}", den[0])
        } else {
            format!("{n}/({})", den.join(" "))
        }
    }

    /// A plain sum of terms (no grouping); a positive term leads when there is one.
    fn sum(&mut self, p: &Poly) -> String {
        let mut terms: Vec<(Mono, f64)> = p.0.iter().map(|(m, c)| (m.clone(), *c)).collect();
        if let Some(k) = terms.iter().position(|(_, c)| *c > 0.0) {
            let t = terms.remove(k);
            terms.insert(0, t);
        }
        let parts: Vec<(bool, String)> = terms
            .iter()
            .map(|(m, c)| (*c < 0.0, self.product(*c, m, None)))
            .collect();
        join_signed(&parts, self.latex)
    }

    /// Groups terms by their state part and renders them with parameter coefficients.
    fn grouped(&mut self, p: &Poly) -> String {
        let parts = self.grouped_parts(p);
        join_signed(&parts, self.latex)
    }

    /// The signed terms of [`Printer::grouped`], before they are joined.
    fn grouped_parts(&mut self, p: &Poly) -> Vec<(bool, String)> {
        let mut groups: BTreeMap<Mono, Poly> = BTreeMap::new();
        for (m, c) in &p.0 {
            let (par, st): (Mono, Mono) = m.iter().partition(|(a, _)| a.is_param());
            groups.entry(st).or_default().0.insert(par, *c);
        }
        // Acceleration terms first, then by the state part.
        let mut keys: Vec<Mono> = groups.keys().cloned().collect();
        keys.sort_by_key(|m| {
            let acc = m.iter().find_map(|(a, _)| match a {
                Atom::A(i) => Some(*i),
                _ => None,
            });
            (acc.is_none(), acc)
        });
        let mut parts = Vec::new();
        for st in keys {
            let Some(coef) = groups.get(&st) else {
                continue;
            };
            if let Some((par, c)) = coef.single() {
                let mut atoms = par.clone();
                atoms.extend(st.iter().copied());
                parts.push((c < 0.0, self.product(c, &atoms, None)));
                continue;
            }
            // Common numeric factor, and a leading sign when all are negative.
            let first = coef.0.values().next().copied().unwrap_or(1.0);
            let same = coef.0.values().all(|c| c.abs() == first.abs());
            let all_neg = coef.0.values().all(|c| *c < 0.0);
            let mut k = if same { first.abs() } else { 1.0 };
            if all_neg {
                k = -k;
            }
            let inner = coef.scale(1.0 / k);
            let inner = self.sum(&inner);
            let inner = self.paren(inner);
            if st.is_empty() && k.abs() == 1.0 {
                parts.push((k < 0.0, inner));
            } else {
                parts.push((k < 0.0, self.product(k, &st, Some(inner))));
            }
        }
        parts
    }
}

fn join_signed(parts: &[(bool, String)], latex: bool) -> String {
    if parts.is_empty() {
        return "0".to_owned();
    }
    let minus = if latex { "-" } else { "−" };
    let mut s = String::new();
    for (k, (neg, t)) in parts.iter().enumerate() {
        match (k, neg) {
            (0, true) => {
                s.push_str(minus);
            }
            (0, false) => {}
            (_, true) => {
                let _ = write!(s, " {minus} ");
            }
            (_, false) => s.push_str(" + "),
        }
        s.push_str(t);
    }
    s
}

/// `p` with every pair of terms `k r sinᵃ⁺²(x) cosᵇ(x) + k r sinᵃ(x) cosᵇ⁺²(x)` (the same k and
/// r) merged into `k r sinᵃ(x) cosᵇ(x)` (sin² + cos² = 1), repeatedly: a 10-link chain's mass
/// entry `10 l² m sin²(q[0]) + 10 l² m cos²(q[0])` prints as `10 l² m`. Only pairs merge, so an
/// equation never gets longer (`cos²` alone is not rewritten as `1 − sin²`).
fn pythagoras(p: &Poly) -> Poly {
    let cos_of = |a: Atom| match a {
        Atom::Fun(Fun::Sin, x) => Some(Atom::Fun(Fun::Cos, x)),
        _ => None,
    };
    let mut p = p.clone();
    while poly::merge_pythagorean(&mut p, &cos_of) {}
    while merge_difference(&mut p) {
        while poly::merge_pythagorean(&mut p, &cos_of) {}
    }
    p
}

/// One merge of k r sin a sin b + k r cos a cos b into k r cos(a − b), or of
/// k r sin a cos b − k r cos a sin b into k r sin(a − b) (a, b in the atoms' order); whether one
/// was made. Printing only: in code the products of sines and cosines already computed are
/// cheaper than another cos.
fn merge_difference(p: &mut Poly) -> bool {
    use poly::shifted;
    let mut found = None;
    'search: for (m, &c) in &p.0 {
        for &(sa, e1) in m {
            let Atom::Fun(Fun::Sin, a) = sa else { continue };
            for &(other, e2) in m {
                let (b, kind) = match other {
                    Atom::Fun(Fun::Sin, b) if b > a => (b, Fun::Cos),
                    Atom::Fun(Fun::Cos, b) if b != a => (b, Fun::Sin),
                    _ => continue,
                };
                if e1 != 1 || e2 != 1 {
                    continue;
                }
                let (ca, sb, cb) = (
                    Atom::Fun(Fun::Cos, a),
                    Atom::Fun(Fun::Sin, b),
                    Atom::Fun(Fun::Cos, b),
                );
                // The partner: cos a cos b (for sin a sin b), cos a sin b (for sin a cos b).
                let rest = shifted(&shifted(m, sa, -1), other, -1);
                let partner = match kind {
                    Fun::Cos => shifted(&shifted(&rest, ca, 1), cb, 1),
                    _ => shifted(&shifted(&rest, ca, 1), sb, 1),
                };
                let Some(&c2) = p.0.get(&partner) else {
                    continue;
                };
                let want = if kind == Fun::Cos { c } else { -c };
                if (want - c2).abs() > 1e-14 * c.abs().max(c2.abs()) {
                    continue;
                }
                let (lo, hi, sign) = if a < b { (a, b, 1.0) } else { (b, a, -1.0) };
                // sin(b − a) = −sin(a − b); cos is even.
                let k = if kind == Fun::Sin { c * sign } else { c };
                let merged = shifted(&rest, Atom::Diff(kind, lo, hi), 1);
                found = Some((m.clone(), partner, merged, k));
                break 'search;
            }
        }
    }
    let Some((m, partner, merged, k)) = found else {
        return false;
    };
    p.0.remove(&m);
    p.0.remove(&partner);
    poly::accumulate(p, merged, k);
    true
}

/// The longest equation printed in full (left and right sides together, in bytes).
const MAX_EQUATION_CHARS: usize = 64 * 1024;

/// What a sub-expression longer than [`MAX_EQUATION_CHARS`] renders as (never printed: the
/// equation containing it is replaced by a note).
const TOO_LONG: &str = "\u{2063}too long\u{2063}";

/// Prints the Euler–Lagrange equation of every coordinate, `Σₖ Mᵢₖ q̈ₖ = fᵢ`, followed on the
/// right by the generalized force Qᵢ and then the dissipative force −∂D/∂q̇ᵢ, each as its own
/// group of terms (so a reader sees where each term comes from).
pub(super) fn equations(d: &Derivation, decl: &Decl) -> Equations {
    let mut slots = Vec::new();
    for c in &decl.coords {
        let name = unraw(&c.name);
        match c.kind {
            CoordKind::Scalar => slots.push(symbol(&name)),
            CoordKind::Vector3 => {
                for comp in ["x", "y", "z"] {
                    let mut s = symbol(&name);
                    s.sub_u = format!("{}.{comp}", s.sub_u);
                    s.sub_l = format!("{}_{{{comp}}}", s.sub_l);
                    slots.push(s);
                }
            }
            CoordKind::Array(k) => {
                for i in 0..k {
                    let mut s = symbol(&name);
                    s.sub_u = format!("{}[{i}]", s.sub_u);
                    s.sub_l = if s.sub_l.is_empty() {
                        format!("_{{{i}}}")
                    } else {
                        format!("{}{{}}_{{{i}}}", s.sub_l)
                    };
                    slots.push(s);
                }
            }
        }
    }
    let params = d
        .fields
        .iter()
        .map(|f| {
            if let Some((base, k)) = f.opaque.as_ref().and_then(|_| element_of(&f.name)) {
                // An element of an array field: `m[3]`.
                let s = symbol(base);
                return (
                    format!("{}{}[{k}]", s.base_u, s.sub_u),
                    format!("{}{}_{{{k}}}", s.base_l, s.sub_l),
                );
            }
            if f.opaque.is_some() {
                // Parameter-only code as written: `(n as f64)`.
                let l = f.name.replace('_', "\\_");
                return (format!("({})", f.name), format!("(\\texttt{{{l}}})"));
            }
            let s = symbol(&f.name);
            let u = format!("{}{}", s.base_u, s.sub_u);
            let l = format!("{}{}", s.base_l, s.sub_l);
            (u, l)
        })
        .collect::<Vec<_>>();
    let names = decl.coordinate_names();
    let mut out = Equations {
        unicode: String::new(),
        latex: String::new(),
    };
    // One expansion for both renderings.
    let mut ex = Expander {
        dag: &d.dag,
        memo: HashMap::new(),
        work: 0,
        assumed: d.conds.iter().map(|c| c.assumed).collect(),
    };
    for latex in [false, true] {
        let mut pr = Printer {
            ex,
            names: Names {
                slots: slots.iter().map(clone_slot).collect(),
                params: params.clone(),
                conds: d.conds.iter().map(|c| c.text.clone()).collect(),
            },
            latex,
            flat: HashMap::new(),
        };
        let mut text = String::new();
        for i in 0..decl.n() {
            if pr.ex.over_budget() {
                let rest = decl.n() - i;
                let _ = if latex {
                    writeln!(
                        text,
                        "\text{{({rest} more equations, too large to print at compile time)}}"
                    )
                } else {
                    writeln!(text, "({rest} more equations, too large to print at compile time; `mass_matrix` and `pieces` give M and f at run time)")
                };
                break;
            }
            let mut lhs = Poly::default();
            for k in 0..decl.n() {
                let m = if k >= i { d.mass[i][k] } else { d.mass[k][i] };
                let pm = pr.ex.poly(m);
                let term = pm
                    .mul(&Poly::atom(Atom::A(k as u32), 1), &PRINTING)
                    .unwrap_or_else(|| Poly::atom(Atom::Paren(m), 1));
                lhs = plus(&lhs, &term, 1.0);
            }
            let l = pr.grouped(&pythagoras(&lhs));
            let mut parts = Vec::new();
            for id in [d.force[i], d.generalized[i], d.dissipative[i]] {
                let p = pythagoras(&pr.ex.poly(id));
                parts.extend(pr.grouped_parts(&p));
            }
            let mut r = join_signed(&parts, latex);
            let label = names.get(i).cloned().unwrap_or_default();
            if l.len() + r.len() > MAX_EQUATION_CHARS
                || l.contains(TOO_LONG)
                || r.contains(TOO_LONG)
            {
                // Deep nesting (sin(sin(…)) differentiated) can print quadratically long: past the
                // cap the line says so instead of putting megabytes of text into the binary.
                let n = l.len() + r.len();
                let (lhs, rhs) = if latex {
                    (
                        "\\text{(left side)}",
                        format!("\\text{{(too long to print: {n} bytes)}}"),
                    )
                } else {
                    ("(left side)", format!("(too long to print: {n} bytes)"))
                };
                r = rhs;
                let l = lhs;
                if latex {
                    let _ = writeln!(text, "{l} = {r}");
                } else {
                    let _ = writeln!(text, "{label}: {l} = {r}");
                }
                continue;
            }
            if latex {
                let _ = writeln!(text, "{l} = {r}");
            } else {
                let _ = writeln!(text, "{label}: {l} = {r}");
            }
        }
        let text = text.trim_end().to_owned();
        if latex {
            out.latex = text;
        } else {
            out.unicode = text;
        }
        ex = pr.ex;
    }
    out
}

fn clone_slot(s: &SlotName) -> SlotName {
    SlotName {
        base_u: s.base_u.clone(),
        base_l: s.base_l.clone(),
        single: s.single,
        sub_u: s.sub_u.clone(),
        sub_l: s.sub_l.clone(),
    }
}

/// `m[3]` → (`m`, 3): an element of an array field, indexed by a number.
fn element_of(text: &str) -> Option<(&str, usize)> {
    let (base, rest) = text.split_once('[')?;
    let k = rest.strip_suffix(']')?.parse().ok()?;
    let ident = !base.is_empty()
        && base.chars().all(|c| c.is_alphanumeric() || c == '_')
        && !base.starts_with(|c: char| c.is_ascii_digit());
    ident.then_some((base, k))
}
