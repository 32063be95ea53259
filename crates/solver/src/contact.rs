//! Contact laws: how a stop acts when its gap `g` closes ([`scene::StopLaw`]),
//! as the questions the solver, the quantities and the front ends ask of it.
//! Each question is one exhaustive `match` here, so that a new law does not
//! compile until every question has its answer (a question asked as "is it
//! soft?" at each use would skip a new law silently).
//!
//! - **Rigid** (restitution `R`): an impact where the gap closes, Newton's law
//!   `ġ⁺ = −R ġ⁻` along the gap's normal; the stop may hold its mass (sticking,
//!   the end of a chatter sequence) and admits no penetration.
//! - **Soft** (stiffness `k`, damping `c`): no impact; while the gap is closed
//!   (`g < 0`) the force `−k g − c ġ` pushes it open (never pulls): a contact
//!   that begins and ends, pressing into the stop.

use scene::{LawKind, StopLaw};

/// A soft stop's spring and dashpot, acting while its gap is closed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Contact stiffness `k` (force per length).
    pub stiffness: f64,
    /// Contact damping `c` (force per velocity).
    pub damping: f64,
}

impl Spring {
    /// The force `−k g − c ġ` at gap `g` and gap rate `ġ` (positive while it
    /// pushes the gap open).
    pub fn force(self, gap: f64, rate: f64) -> f64 {
        -self.stiffness * gap - self.damping * rate
    }

    /// The elastic energy `k g² / 2` stored at gap `g` (closed).
    pub fn energy(self, gap: f64) -> f64 {
        0.5 * self.stiffness * gap.powi(2)
    }
}

/// What the events of a stop obeying `law` are called in tables and figures:
/// `impacts`, or `contacts` begun.
pub fn events(law: LawKind) -> &'static str {
    match law {
        LawKind::Rigid => "impacts",
        LawKind::Soft => "contacts",
    }
}

/// The questions asked of a stop's contact law.
pub trait Contact {
    /// Whether the stop acts by impacts, events that map the velocities, and
    /// may hold its mass against it (sticking, the end of a chatter sequence).
    fn impacts(&self) -> bool;

    /// The coefficient of restitution of its impacts; `None` without impacts.
    fn restitution(&self) -> Option<f64>;

    /// Its spring and dashpot while pressed; `None` for a stop without one.
    fn spring(&self) -> Option<Spring>;

    /// Whether a state may press into the stop (a spring takes up the
    /// penetration); otherwise it admits none beyond rounding.
    fn yields(&self) -> bool;

    /// What its events are called in tables and figures: `impacts`, or
    /// `contacts` begun.
    fn events(&self) -> &'static str;
}

impl Contact for StopLaw {
    fn impacts(&self) -> bool {
        match self {
            StopLaw::Rigid { .. } => true,
            StopLaw::Soft { .. } => false,
        }
    }

    fn restitution(&self) -> Option<f64> {
        match *self {
            StopLaw::Rigid { restitution } => Some(restitution),
            StopLaw::Soft { .. } => None,
        }
    }

    fn spring(&self) -> Option<Spring> {
        match *self {
            StopLaw::Rigid { .. } => None,
            StopLaw::Soft { stiffness, damping } => Some(Spring { stiffness, damping }),
        }
    }

    fn yields(&self) -> bool {
        match self {
            StopLaw::Rigid { .. } => false,
            StopLaw::Soft { .. } => true,
        }
    }

    fn events(&self) -> &'static str {
        events(self.kind())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two laws answer as the models page states them: a rigid stop
    /// impacts with its restitution and yields nothing; a soft one pushes
    /// with `−k g − c ġ` and stores `k g²/2`.
    #[test]
    fn each_law_answers_as_its_model() {
        let rigid = StopLaw::Rigid { restitution: 0.8 };
        assert!(rigid.impacts() && !rigid.yields() && rigid.spring().is_none());
        assert_eq!((rigid.restitution(), rigid.events()), (Some(0.8), "impacts"));
        let soft = StopLaw::Soft { stiffness: 100.0, damping: 0.5 };
        assert!(!soft.impacts() && soft.yields() && soft.restitution().is_none());
        let spring = soft.spring().unwrap();
        assert!((spring.force(-0.01, -0.2) - 1.1).abs() < 1e-15 && (spring.energy(-0.01) - 0.005).abs() < 1e-17);
        assert_eq!(soft.events(), "contacts");
    }
}
