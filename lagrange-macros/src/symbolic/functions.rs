//! The elementary functions of one argument, from the one table of `lagrange_functions` (one row
//! each: the method a body calls and the generated code calls, its value for constant folding,
//! its tangent rule, its names for people). Lowering, differentiation, code generation,
//! evaluation and printing read it through here; adding a function is adding a row there.
//!
//! This file holds what the graph needs to apply a rule: [`Build`], the operations a rule builds
//! its result with, and [`Rule::derivative`], the rule applied to graph nodes.

use std::cell::RefCell;
use std::ops::{Add, Div, Mul, Neg, Sub};

pub use lagrange_functions::Fun;
use lagrange_functions::{tangent, Calc};

/// A node id of the expression graph.
pub type Id = u32;

/// The id of the constant 0 in every graph.
pub const ZERO: Id = 0;
/// The id of the constant 1 in every graph.
pub const ONE: Id = 1;

/// The graph operations a derivative rule builds its result with (the DAG provides them): the
/// table needs nothing else of the graph, so it does not depend on it.
pub trait Build {
    /// The constant c.
    fn constant(&mut self, c: f64) -> Id;
    /// a + b.
    fn add(&mut self, a: Id, b: Id) -> Id;
    /// a − b.
    fn sub(&mut self, a: Id, b: Id) -> Id;
    /// a · b.
    fn mul(&mut self, a: Id, b: Id) -> Id;
    /// a / b.
    fn div(&mut self, a: Id, b: Id) -> Id;
    /// −a.
    fn neg(&mut self, a: Id) -> Id;
    /// aⁿ.
    fn powi(&mut self, a: Id, n: i32) -> Id;
    /// f(a).
    fn un(&mut self, f: Fun, a: Id) -> Id;
}

/// The tangent rule of a function applied to graph nodes.
pub trait Rule {
    /// The tangent of `y = f(a)` given the tangent `da` of `a`: the node of f(a), its argument
    /// and the argument's tangent.
    fn derivative(self, dag: &mut dyn Build, y: Id, a: Id, da: Id) -> Id;
}

impl Rule for Fun {
    fn derivative(self, dag: &mut dyn Build, y: Id, a: Id, da: Id) -> Id {
        let g = RefCell::new(dag);
        let node = |id| Node { g: &g, id };
        let k = |c| node(g.borrow_mut().constant(c));
        tangent(self, node(a), node(y), node(da), &k).id
    }
}

/// A node of the graph being built, with the arithmetic of [`Calc`] (each operation adds a node).
#[derive(Clone, Copy)]
struct Node<'g, 'b> {
    g: &'g RefCell<&'b mut dyn Build>,
    id: Id,
}

impl Node<'_, '_> {
    fn with(self, f: impl FnOnce(&mut dyn Build) -> Id) -> Self {
        let id = f(&mut **self.g.borrow_mut());
        Node { g: self.g, id }
    }
}

macro_rules! binary {
    ($($Trait:ident $method:ident),*) => {$(
        impl $Trait for Node<'_, '_> {
            type Output = Self;
            fn $method(self, o: Self) -> Self {
                self.with(|b| b.$method(self.id, o.id))
            }
        }
    )*};
}

binary!(Add add, Sub sub, Mul mul, Div div);

impl Neg for Node<'_, '_> {
    type Output = Self;
    fn neg(self) -> Self {
        self.with(|b| b.neg(self.id))
    }
}

impl Calc for Node<'_, '_> {
    fn sqrt(self) -> Self {
        self.with(|b| b.un(Fun::Sqrt, self.id))
    }
    fn sin(self) -> Self {
        self.with(|b| b.un(Fun::Sin, self.id))
    }
    fn cos(self) -> Self {
        self.with(|b| b.un(Fun::Cos, self.id))
    }
    fn sinh(self) -> Self {
        self.with(|b| b.un(Fun::Sinh, self.id))
    }
    fn cosh(self) -> Self {
        self.with(|b| b.un(Fun::Cosh, self.id))
    }
    fn exp(self) -> Self {
        self.with(|b| b.un(Fun::Exp, self.id))
    }
    fn powi(self, n: i32) -> Self {
        self.with(|b| b.powi(self.id, n))
    }
    fn step(self) -> Self {
        self.with(|b| b.un(Fun::Step, self.id))
    }
}
