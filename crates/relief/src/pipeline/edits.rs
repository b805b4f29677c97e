//! The contour edits of a scene (the contours paper, §5): smoothing, and warps composed in order.

use rayon::prelude::*;

use super::progress::Tick;
use crate::contours::{Contour, ContourSet, Smoothing};
use glam::DVec2;

use crate::error::SceneError;
use crate::scene::{ContourMove, ContourPick, Edit};
use crate::warp::{Composition, Warp, warp_polyline};
use crate::{ReliefError, ReliefError as E};

/// A scene's edits, checked, with its warps composed in order.
pub(super) struct Edits {
    steps: Vec<Step>,
    /// Every warp among the edits, in order: the map backward mapping inverts.
    pub(super) warps: Composition,
    /// The contour tools, with their index among the scene's edits, in order.
    pub(super) tools: Vec<(usize, Tool)>,
}

/// A contour tool of the scene: what it does, the contour it picks, and where it moves it.
#[derive(Clone, Copy)]
pub(super) struct Tool {
    pub(super) kind: ToolKind,
    pub(super) at: DVec2,
    pub(super) height: Option<f64>,
    pub(super) to: DVec2,
}

/// The contour tools.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum ToolKind {
    Fill,
    Delete,
    Paste,
    Cut,
}

impl ToolKind {
    pub(super) fn name(self) -> &'static str {
        match self {
            Self::Fill => "fill",
            Self::Delete => "delete",
            Self::Paste => "paste",
            Self::Cut => "cut",
        }
    }
}

enum Step {
    Smooth(Smoothing),
    /// The warp `warps.get(k)`.
    Warp(usize),
}

impl Edits {
    /// The edits in order; warps were built (and so checked) as the scene was read, smoothing
    /// parameters are checked here, before any heavy work.
    pub(super) fn prepare(edits: &[Edit]) -> Result<Self, ReliefError> {
        let mut out = Self { steps: Vec::with_capacity(edits.len()), warps: Composition::new(), tools: Vec::new() };
        for (i, edit) in edits.iter().enumerate() {
            let pick = |kind, p: &ContourPick| Tool { kind, at: p.at.into(), height: p.height, to: p.at.into() };
            let moved = |kind, m: &ContourMove| Tool { kind, at: m.at.into(), height: m.height, to: m.to.into() };
            let warp: Box<dyn Warp> = match edit {
                Edit::Smooth(s) => {
                    s.validate().map_err(|e| E::located(&format!("edits[{i}].smooth"), e))?;
                    out.steps.push(Step::Smooth(*s));
                    continue;
                }
                Edit::Warp(w) => Box::new(w.clone()),
                Edit::Slope(s) => Box::new(s.clone()),
                Edit::Fill(p) => {
                    out.push_tool(i, pick(ToolKind::Fill, p))?;
                    continue;
                }
                Edit::Delete(p) => {
                    out.push_tool(i, pick(ToolKind::Delete, p))?;
                    continue;
                }
                Edit::Paste(m) => {
                    out.push_tool(i, moved(ToolKind::Paste, m))?;
                    continue;
                }
                Edit::Cut(m) => {
                    out.push_tool(i, moved(ToolKind::Cut, m))?;
                    continue;
                }
            };
            out.steps.push(Step::Warp(out.warps.len()));
            out.warps.push(warp);
        }
        Ok(out)
    }

    /// Adds the contour tool of edit `i`, its points and height checked finite.
    fn push_tool(&mut self, i: usize, tool: Tool) -> Result<(), ReliefError> {
        if !(tool.at.is_finite() && tool.to.is_finite() && tool.height.is_none_or(f64::is_finite)) {
            let at = format!("edits[{i}].{}", tool.kind.name());
            let error = SceneError::OutOfRange { value: "a point or height".into(), rule: "must be finite" };
            return Err(E::at(at, error));
        }
        self.tools.push((i, tool));
        Ok(())
    }

    /// The smoothing edits, in order.
    pub(super) fn smoothings(&self) -> impl Iterator<Item = &Smoothing> {
        self.steps.iter().filter_map(|s| match s {
            Step::Smooth(s) => Some(s),
            Step::Warp(_) => None,
        })
    }

    /// How many contour edits there are: the units of work [`apply_edits`] ticks.
    pub(super) fn len(&self) -> usize {
        self.steps.len()
    }
}

/// Applies the edits to the contours in order, ticking each.
///
/// A warp is a bijection, so warped contours never cross — but their polylines only follow the
/// warped curves to within a tolerance (adaptive subdivision), and where a warp squeezes
/// neighbouring contours closer than that, the approximations could touch. Each warped set is
/// therefore checked, and warped again from the same input with a quarter of the tolerance until
/// it is clean (smoothing guarantees this by construction).
pub(super) fn apply_edits(
    mut set: ContourSet,
    edits: &Edits,
    tolerance: f64,
    tick: &mut Tick<'_>,
) -> Result<ContourSet, ReliefError> {
    for step in &edits.steps {
        set = match step {
            Step::Smooth(s) => set.smoothed(s).map_err(|e| E::step("edits", e))?,
            Step::Warp(k) => match edits.warps.get(*k) {
                Some(warp) => warp_checked(&set, warp, *k, tolerance)?,
                None => set,
            },
        };
        tick.tick();
        tick.check()?;
    }
    Ok(set)
}

/// `set` warped by warp `k`, checked and warped again at a quarter of the tolerance until clean
/// (at most six times).
fn warp_checked(set: &ContourSet, warp: &dyn Warp, k: usize, tolerance: f64) -> Result<ContourSet, ReliefError> {
    const REFINEMENTS: u32 = 6;
    let (mut tol, mut round) = (tolerance, 0);
    loop {
        let warped = warp_set(set, warp, tol)?;
        match warped.check_invariants() {
            Ok(()) => return Ok(warped),
            Err(e) if round == REFINEMENTS => {
                return Err(E::step("edits", format!("warp {k}: {e} at tolerance {tol}")));
            }
            Err(_) => (tol, round) = (tol * 0.25, round + 1),
        }
    }
}

/// Every contour of `set` warped to within `tolerance`.
fn warp_set(set: &ContourSet, warp: &dyn Warp, tolerance: f64) -> Result<ContourSet, ReliefError> {
    let contours: Vec<Contour> = set
        .contours()
        .par_iter()
        .map(|c| {
            let points = warp_polyline(warp, &c.points, c.closed, tolerance).map_err(|e| E::step("edits", e))?;
            Ok(Contour { points, ..c.clone() })
        })
        .collect::<Result<_, ReliefError>>()?;
    ContourSet::new(set.levels().to_vec(), contours).map_err(|e| E::step("edits", e))
}
