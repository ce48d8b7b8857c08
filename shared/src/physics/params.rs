//! Physical parameters, effect switches and model choices of one simulation.

use serde::{Deserialize, Serialize};

use super::table::TableKind;

// Heated carom cloth, carom balls and cushions: fitted once to 40 shots recorded on real
// three-cushion tables by `breakshot-sim fit` (Han 2005 cushions), starting from the pool
// values below and kept within physical ranges (docs/reality.md).
const CAROM_MU_SLIDE: f64 = 0.229;
const CAROM_MU_ROLL: f64 = 0.0045;
const CAROM_MU_SPIN: f64 = 0.0058;
const CAROM_E_BALL: f64 = 0.962;
const CAROM_E_CUSHION: f64 = 0.80;
const CAROM_F_CUSHION: f64 = 0.292;

// Snooker balls and cloth. Mathavan, Jackson and Parkin, "A theoretical analysis of billiard
// ball dynamics under cushion impacts", Proc. IMechE C 224 (2010), measured on a snooker
// table: ball 0.1406 kg, ball–cloth sliding friction 0.212, ball–cushion restitution 0.98
// and sliding friction 0.14, the cushion nose at 7R/5. The ball's size is the WPBSA's
// (52.5 mm). Rolling and spin friction of snooker cloth have no published measurement we
// could use: the pool cloth's stand.
const SNOOKER_BALL_RADIUS: f64 = 0.02625;
const SNOOKER_BALL_MASS: f64 = 0.1406;
const SNOOKER_MU_SLIDE: f64 = 0.212;
const SNOOKER_E_CUSHION: f64 = 0.98;
const SNOOKER_F_CUSHION: f64 = 0.14;
const SNOOKER_CUSHION_HEIGHT: f64 = 1.4 * SNOOKER_BALL_RADIUS;

/// Ball–ball friction: a constant, or Alciatore's fit μ(v) = a + b·exp(−c·v) of the
/// relative surface speed at the contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum BallFriction {
    /// The same μ at every speed (a scene writes a plain number).
    Constant(f64),
    /// μ = a + b·exp(−c·v_rel), written `{"a", "b", "c"}`.
    SpeedDependent {
        /// The limit of μ at high speed.
        a: f64,
        /// How much more μ is at zero relative speed.
        b: f64,
        /// How fast the extra friction fades (s/m).
        c: f64,
    },
}

impl BallFriction {
    /// The friction coefficient at relative surface speed `v_rel` (m/s).
    pub fn at(&self, v_rel: f64) -> f64 {
        match *self {
            BallFriction::Constant(mu) => mu,
            BallFriction::SpeedDependent { a, b, c } => a + b * libm::exp(-c * v_rel),
        }
    }
}

/// Physical constants. The defaults are pooltool 0.6.0's, taken from the literature.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Params {
    /// Ball radius R (m).
    pub ball_radius: f64,
    /// Ball mass m (kg).
    pub ball_mass: f64,
    /// Gravitational acceleration g (m/s²).
    pub gravity: f64,
    /// Ball–cloth sliding friction coefficient.
    pub mu_slide: f64,
    /// Rolling resistance: a rolling ball decelerates at `mu_roll·g`.
    pub mu_roll: f64,
    /// Spin friction length (m): spin about the vertical decays at 5·mu_spin·g/(2R).
    pub mu_spin: f64,
    /// Ball–ball coefficient of restitution.
    pub e_ball: f64,
    /// Ball–ball friction.
    pub ball_friction: BallFriction,
    /// Ball–cushion coefficient of restitution.
    pub e_cushion: f64,
    /// Ball–cushion friction coefficient.
    pub f_cushion: f64,
    /// Height of the cushion nose above the cloth (m).
    pub cushion_height: f64,
    /// Ball–table (slate) coefficient of restitution, for a ball landing or driven into it.
    pub e_table: f64,
    /// Rolling resistance as the founding paper gives it, Heathcote's law
    /// `F = k·W^(5/3)/R^(4/3)`; when present it replaces `mu_roll` (see
    /// [`Params::mu_roll_from_heathcote`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub heathcote_k: Option<f64>,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            ball_radius: 0.028575,
            ball_mass: 0.170097,
            gravity: 9.81,
            mu_slide: 0.2,
            mu_roll: 0.01,
            mu_spin: 0.0127,
            e_ball: 0.95,
            ball_friction: BallFriction::SpeedDependent {
                a: 0.009951,
                b: 0.108,
                c: 1.088,
            },
            e_cushion: 0.85,
            f_cushion: 0.2,
            cushion_height: 0.036576,
            e_table: 0.5,
            heathcote_k: None,
        }
    }
}

impl Params {
    /// The default parameters of a table: pool balls and cloth for the pool tables and the
    /// open cloth, snooker balls on snooker cloth for the snooker table (docs/physics.md,
    /// "The snooker table"), carom balls on heated cloth for the carom table (docs/physics.md, "The
    /// carom table", gives the sources and how the cloth and cushion constants were fitted to
    /// recorded shots).
    pub fn for_table(kind: TableKind) -> Params {
        match kind {
            TableKind::Carom => Params {
                // UMB: balls of 61–61.5 mm and 205–220 g.
                ball_radius: 0.03075,
                ball_mass: 0.21,
                // UMB: cushion nose 37 mm ± 1 mm above the bed.
                cushion_height: 0.037,
                mu_slide: CAROM_MU_SLIDE,
                mu_roll: CAROM_MU_ROLL,
                mu_spin: CAROM_MU_SPIN,
                e_ball: CAROM_E_BALL,
                e_cushion: CAROM_E_CUSHION,
                f_cushion: CAROM_F_CUSHION,
                ..Params::default()
            },
            TableKind::Snooker => Params {
                ball_radius: SNOOKER_BALL_RADIUS,
                ball_mass: SNOOKER_BALL_MASS,
                mu_slide: SNOOKER_MU_SLIDE,
                e_cushion: SNOOKER_E_CUSHION,
                f_cushion: SNOOKER_F_CUSHION,
                cushion_height: SNOOKER_CUSHION_HEIGHT,
                ..Params::default()
            },
            _ => Params::default(),
        }
    }

    /// Every parameter with its name, for validation and messages (an array, not a vector:
    /// validation runs before every simulation and must not allocate).
    pub fn named_values(&self) -> [(&'static str, f64); 14] {
        let (fa, fb, fc, names) = match self.ball_friction {
            BallFriction::Constant(mu) => (mu, 0.0, 0.0, ["ball_friction"; 3]),
            BallFriction::SpeedDependent { a, b, c } => (
                a,
                b,
                c,
                ["ball_friction.a", "ball_friction.b", "ball_friction.c"],
            ),
        };
        [
            ("ball_radius", self.ball_radius),
            ("ball_mass", self.ball_mass),
            ("gravity", self.gravity),
            ("mu_slide", self.mu_slide),
            ("mu_roll", self.mu_roll),
            ("mu_spin", self.mu_spin),
            ("e_ball", self.e_ball),
            ("e_cushion", self.e_cushion),
            ("f_cushion", self.f_cushion),
            ("cushion_height", self.cushion_height),
            ("e_table", self.e_table),
            (names[0], fa),
            (names[1], fb),
            (names[2], fc),
        ]
    }

    /// The rolling resistance coefficient in force: `mu_roll`, or Heathcote's `k` converted.
    pub fn rolling_resistance(&self) -> f64 {
        match self.heathcote_k {
            Some(k) => self.mu_roll_from_heathcote(k),
            None => self.mu_roll,
        }
    }

    /// Checks that every parameter is finite and in its physical range.
    pub fn validate(&self) -> Result<(), String> {
        if let Some(k) = self.heathcote_k {
            if !k.is_finite() || k < 0.0 {
                return Err("physics.heathcote_k must be a finite, non-negative number".into());
            }
        }
        for (name, value) in self.named_values() {
            if !value.is_finite() {
                return Err(format!("physics.{name} must be a finite number"));
            }
            if value < 0.0 {
                return Err(format!("physics.{name} must not be negative"));
            }
        }
        let positive = [
            ("ball_radius", self.ball_radius),
            ("ball_mass", self.ball_mass),
            ("gravity", self.gravity),
        ];
        for (name, value) in positive {
            if value <= 0.0 {
                return Err(format!("physics.{name} must be positive"));
            }
        }
        if self.ball_radius > 1.0 {
            return Err("physics.ball_radius must be at most 1 m".into());
        }
        for (name, value) in [
            ("e_ball", self.e_ball),
            ("e_cushion", self.e_cushion),
            ("e_table", self.e_table),
        ] {
            if value > 1.0 {
                return Err(format!("physics.{name} must be between 0 and 1"));
            }
        }
        if self.cushion_height < self.ball_radius || self.cushion_height >= 2.0 * self.ball_radius {
            return Err("physics.cushion_height must be between R and 2R".into());
        }
        Ok(())
    }

    /// Moment of inertia factor: I = 2/5·m·R² for a solid sphere.
    pub fn inertia(&self) -> f64 {
        0.4 * self.ball_mass * self.ball_radius * self.ball_radius
    }

    /// Angular deceleration of spin about the vertical (rad/s²).
    pub fn spin_decel(&self) -> f64 {
        5.0 * self.mu_spin * self.gravity / (2.0 * self.ball_radius)
    }

    /// Rolling resistance expressed as Heathcote's law F = k·W^(5/3)/R^(4/3)
    /// (the founding paper's form): the `k` that gives the same force as `mu_roll`.
    /// With W = m·g, F = mu_roll·W, so k = mu_roll·R^(4/3)/W^(2/3).
    pub fn heathcote_k(&self) -> f64 {
        let w = self.ball_mass * self.gravity;
        self.mu_roll * libm::pow(self.ball_radius, 4.0 / 3.0) / libm::pow(w, 2.0 / 3.0)
    }

    /// The inverse of [`Params::heathcote_k`]: the `mu_roll` that Heathcote's `k` gives.
    pub fn mu_roll_from_heathcote(&self, k: f64) -> f64 {
        let w = self.ball_mass * self.gravity;
        k * libm::pow(w, 2.0 / 3.0) / libm::pow(self.ball_radius, 4.0 / 3.0)
    }
}

/// Switches for each effect. An effect that is off is not simulated and costs nothing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Effects {
    /// Sliding balls lose slip to the cloth; when off they keep their velocity and spin.
    pub slide_friction: bool,
    /// Rolling balls slow down; when off they roll on for ever.
    pub roll_friction: bool,
    /// Spin about the vertical decays; when off it lasts.
    pub spin_friction: bool,
    /// Ball–ball contacts transfer a tangential impulse (throw, spin transfer).
    pub ball_friction: bool,
    /// The rails stop balls; when off, balls are not stopped by them.
    pub cushions: bool,
    /// Balls fall into pockets; when off the rails run unbroken, as on a carom table.
    pub pockets: bool,
    /// Balls leave the cloth: an elevated strike drives the ball into the slate and it may
    /// bounce up; when off, the slate takes the vertical part of every impulse.
    pub airborne: bool,
}

impl Default for Effects {
    fn default() -> Self {
        Effects {
            slide_friction: true,
            roll_friction: true,
            spin_friction: true,
            ball_friction: true,
            cushions: true,
            pockets: true,
            airborne: true,
        }
    }
}

impl Effects {
    /// Every effect off: balls keep their velocity until they meet something.
    pub fn none() -> Self {
        Effects {
            slide_friction: false,
            roll_friction: false,
            spin_friction: false,
            ball_friction: false,
            cushions: false,
            pockets: false,
            airborne: false,
        }
    }

    /// True when every moving ball eventually stops by itself.
    pub fn balls_come_to_rest(&self) -> bool {
        self.slide_friction && self.roll_friction && self.spin_friction
    }
}

/// Ball–ball collision model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BallBallModel {
    /// Frictionless, perfectly elastic, equal masses: the velocity components along the line
    /// of centres are exchanged and nothing else changes (the founding paper's model).
    Ideal,
    /// Restitution `e_ball` and Coulomb friction between the balls (throw, spin transfer).
    #[default]
    Frictional,
}

/// Ball–cushion collision model.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CushionModel {
    /// Han (2005): impulses at the cushion nose, with restitution and friction.
    #[default]
    Han2005,
    /// Mathavan, Jackson and Parkin (2010): the compression and restitution phases integrated
    /// over the normal impulse, with slip at the cushion and at the cloth.
    Mathavan2010,
    /// Stronge's compliant-contact frictional impact, as pooltool 0.6.0 applies it to
    /// cushions.
    Stronge,
    /// Mirror reflection of the normal velocity scaled by `e_cushion`; spin unchanged.
    Simple,
}

/// Model choices of one simulation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Models {
    /// How two balls collide; frictional by default.
    pub ball_ball: BallBallModel,
    /// How a ball bounces off a rail or a jaw; Han (2005) by default.
    pub cushion: CushionModel,
}
