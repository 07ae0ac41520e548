//! The distance function compiled to a flat instruction array, evaluated by a loop over two
//! small fixed-size stacks (values, and points for the nested frames) instead of recursing
//! through boxed nodes: no pointer chasing, no calls, no allocation.
//!
//! Postfix order: a primitive pushes its value at the current point; a binary operator pops
//! two values and pushes one; a transform pushes the transformed point before its operand's
//! code and pops it after (a scale also multiplies the value by s).

use super::node::{Node, repeat_point, smin, twist_point};
use glam::{DMat3, DVec3};

/// Stack depth the evaluator provides; deeper programs are not compiled (the tree is used).
pub const STACK: usize = 8;

/// A change of frame.
#[derive(Clone, Debug, PartialEq)]
enum Frame {
    Translate(DVec3),
    Rotate(DMat3),
    Scale(f64),
    Twist(f64),
    Repeat(DVec3, Option<DVec3>),
}

/// One instruction.
#[derive(Clone, Debug, PartialEq)]
enum Op {
    /// A primitive's value at the current point.
    Prim(Node),
    Min,
    Max,
    /// max(a, −b).
    MaxNeg,
    SMin(f64),
    /// −smin(−a, −b, k).
    SMax(f64),
    /// −smin(−a, b, k).
    SDiff(f64),
    Push(Frame),
    Pop,
    /// Pop the frame and multiply the value by s.
    PopScale(f64),
}

/// A compiled distance function.
#[derive(Clone, Debug, PartialEq)]
pub struct Program {
    ops: Vec<Op>,
}

struct Emitter {
    ops: Vec<Op>,
    vals: usize,
    max_vals: usize,
    frames: usize,
    max_frames: usize,
}

impl Emitter {
    fn push_val(&mut self) {
        self.vals += 1;
        self.max_vals = self.max_vals.max(self.vals);
    }

    fn binary(&mut self, op: Op) {
        self.ops.push(op);
        self.vals -= 1;
    }

    fn framed(&mut self, frame: Frame, e: &Node, pop: Op) {
        self.ops.push(Op::Push(frame));
        self.frames += 1;
        self.max_frames = self.max_frames.max(self.frames);
        self.emit(e);
        self.ops.push(pop);
        self.frames -= 1;
    }

    fn emit(&mut self, n: &Node) {
        match n {
            Node::Union(v) | Node::Intersection(v) | Node::Difference(v) => {
                let op = match n {
                    Node::Union(_) => Op::Min,
                    Node::Intersection(_) => Op::Max,
                    _ => Op::MaxNeg,
                };
                self.emit(&v[0]);
                for c in &v[1..] {
                    self.emit(c);
                    self.binary(op.clone());
                }
            }
            Node::SmoothUnion(a, b, k)
            | Node::SmoothIntersection(a, b, k)
            | Node::SmoothDifference(a, b, k) => {
                self.emit(a);
                self.emit(b);
                self.binary(match n {
                    Node::SmoothUnion(..) => Op::SMin(*k),
                    Node::SmoothIntersection(..) => Op::SMax(*k),
                    _ => Op::SDiff(*k),
                });
            }
            Node::Translate(v, e) => self.framed(Frame::Translate(*v), e, Op::Pop),
            Node::Rotate(m, e) => self.framed(Frame::Rotate(*m), e, Op::Pop),
            Node::Scale(s, e) => self.framed(Frame::Scale(*s), e, Op::PopScale(*s)),
            Node::Twist(k, e) => self.framed(Frame::Twist(*k), e, Op::Pop),
            Node::Repeat(c, cnt, e) => self.framed(Frame::Repeat(*c, *cnt), e, Op::Pop),
            prim => {
                self.ops.push(Op::Prim(prim.clone()));
                self.push_val();
            }
        }
    }
}

impl Program {
    /// Compiles a tree; `None` when it needs more than [`STACK`] levels of either stack.
    pub fn compile(root: &Node) -> Option<Program> {
        let mut e = Emitter {
            ops: Vec::new(),
            vals: 0,
            max_vals: 0,
            frames: 0,
            max_frames: 0,
        };
        e.emit(root);
        (e.max_vals <= STACK && e.max_frames < STACK).then_some(Program { ops: e.ops })
    }

    /// Number of instructions.
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// True for an empty program (never produced by [`Program::compile`]).
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// The function's value at `p`.
    pub fn eval(&self, p: DVec3) -> f64 {
        let mut vals = [0.0f64; STACK];
        let mut pts = [DVec3::ZERO; STACK];
        let (mut nv, mut np) = (0usize, 1usize);
        pts[0] = p;
        for op in &self.ops {
            match op {
                Op::Prim(n) => {
                    vals[nv] = n.eval(pts[np - 1]);
                    nv += 1;
                }
                Op::Min | Op::Max | Op::MaxNeg | Op::SMin(_) | Op::SMax(_) | Op::SDiff(_) => {
                    nv -= 1;
                    let (a, b) = (vals[nv - 1], vals[nv]);
                    vals[nv - 1] = match op {
                        Op::Min => a.min(b),
                        Op::Max => a.max(b),
                        Op::MaxNeg => a.max(-b),
                        Op::SMin(k) => smin(a, b, *k),
                        Op::SMax(k) => -smin(-a, -b, *k),
                        Op::SDiff(k) => -smin(-a, b, *k),
                        _ => unreachable!("binary operators only"),
                    };
                }
                Op::Push(f) => {
                    let q = pts[np - 1];
                    pts[np] = match f {
                        Frame::Translate(v) => q - *v,
                        Frame::Rotate(m) => *m * q,
                        Frame::Scale(s) => q / *s,
                        Frame::Twist(k) => twist_point(*k, q),
                        Frame::Repeat(c, n) => repeat_point(*c, n.as_ref(), q),
                    };
                    np += 1;
                }
                Op::Pop => np -= 1,
                Op::PopScale(s) => {
                    np -= 1;
                    vals[nv - 1] *= s;
                }
            }
        }
        vals[0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::sdf::SdfFunction;

    #[test]
    fn flat_program_equals_the_tree() {
        let f = SdfFunction::parse(
            "union(twist(1, box([0.3, 1, 0.2])), translate([1, 0, 0], difference(sphere(0.5), \
             cylinder(1, 0.2), box([0.1, 1, 1]))), repeat([0.5, 0, 0.5], [2, 0, 2], \
             capsule([0, 0, 0], [0, 0.3, 0], 0.1)), scale(0.5, rotate(20, [1, 0, 0], \
             smooth_difference(cone(0.5, 1), smooth_intersection(torus(1, 0.2), \
             ellipsoid([0.2, 0.3, 0.4]), 0.1), 0.2))))",
        )
        .unwrap();
        let prog = Program::compile(f.root()).unwrap();
        for i in 0..2000 {
            let x = i as f64;
            let p = DVec3::new((x * 0.37).sin(), (x * 0.11).cos(), (x * 0.23).sin()) * 2.0;
            assert_eq!(prog.eval(p), f.eval(p), "{p}");
        }
    }
}
