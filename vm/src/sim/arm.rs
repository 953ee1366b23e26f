//! The arm's kinematic model: a base yaw joint, then a two-link arm in the vertical plane
//! (shoulder and elbow pitch), and a passive wrist that keeps the gripper pointing down, so
//! the gripper's position is the end of the second link.
//!
//! Motions are straight lines of the gripper in Cartesian space, followed step by step: each
//! step moves along the line by at most the Cartesian speed, and by less where a joint would
//! otherwise turn faster than its speed limit; the joints come from inverse kinematics
//! (elbow up) at every point. A line that leaves the arm's reach is refused before it starts.

use nalgebra::Vector3;

/// Joint angles in radians: base yaw, shoulder pitch (from the horizontal), elbow bend.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Joints {
    /// Rotation about the vertical axis.
    pub yaw: f64,
    /// First link's elevation.
    pub shoulder: f64,
    /// Bend between the links (0: straight).
    pub elbow: f64,
}

/// An arm's fixed geometry and limits.
#[derive(Clone, Debug)]
pub struct ArmModel {
    /// The shoulder joint's position (metres, world frame, z up).
    pub shoulder: Vector3<f64>,
    /// First link length.
    pub upper: f64,
    /// Second link length.
    pub fore: f64,
    /// Joint speed limit, radians per second (every joint).
    pub joint_speed: f64,
    /// Gripper speed limit along a line, metres per second.
    pub linear_speed: f64,
}

impl ArmModel {
    /// The joints that put the gripper at `target`, elbow up, or `None` out of reach.
    pub fn inverse(&self, target: Vector3<f64>) -> Option<Joints> {
        let d = target - self.shoulder;
        let r = (d.x * d.x + d.y * d.y).sqrt();
        let dist = (r * r + d.z * d.z).sqrt();
        let (a, b) = (self.upper, self.fore);
        if dist > a + b - 1e-6 || dist < (a - b).abs() + 1e-6 {
            return None;
        }
        let cos_elbow = ((dist * dist - a * a - b * b) / (2.0 * a * b)).clamp(-1.0, 1.0);
        let elbow = cos_elbow.acos();
        let shoulder = d.z.atan2(r) + (b * elbow.sin()).atan2(a + b * elbow.cos());
        Some(Joints { yaw: d.y.atan2(d.x), shoulder, elbow })
    }

    /// Where the elbow (the end of the first link) is for `joints`.
    pub fn elbow(&self, joints: Joints) -> Vector3<f64> {
        let r = self.upper * joints.shoulder.cos();
        self.shoulder + Vector3::new(r * joints.yaw.cos(), r * joints.yaw.sin(), self.upper * joints.shoulder.sin())
    }

    /// Where the gripper is for `joints`.
    pub fn forward(&self, joints: Joints) -> Vector3<f64> {
        let r = self.upper * joints.shoulder.cos() + self.fore * (joints.shoulder - joints.elbow).cos();
        let z = self.upper * joints.shoulder.sin() + self.fore * (joints.shoulder - joints.elbow).sin();
        self.shoulder + Vector3::new(r * joints.yaw.cos(), r * joints.yaw.sin(), z)
    }

    /// Whether every point of the line from `from` to `to` is within reach (checked every
    /// centimetre).
    pub fn reaches_line(&self, from: Vector3<f64>, to: Vector3<f64>) -> bool {
        let samples = ((to - from).norm() / 0.01).ceil().max(1.0) as usize;
        (0..=samples).all(|i| self.inverse(from.lerp(&to, i as f64 / samples as f64)).is_some())
    }
}

/// The largest change of any joint between two configurations (yaw the short way round).
pub fn joint_distance(a: Joints, b: Joints) -> f64 {
    let mut yaw = (b.yaw - a.yaw).rem_euclid(std::f64::consts::TAU);
    if yaw > std::f64::consts::PI {
        yaw = std::f64::consts::TAU - yaw;
    }
    yaw.max((b.shoulder - a.shoulder).abs()).max((b.elbow - a.elbow).abs())
}

/// A straight-line motion of the gripper being followed.
#[derive(Clone, Debug)]
pub struct Line {
    from: Vector3<f64>,
    to: Vector3<f64>,
    /// How far along, 0 to 1.
    progress: f64,
}

impl Line {
    /// A line from `from` to `to`.
    pub fn new(from: Vector3<f64>, to: Vector3<f64>) -> Line {
        Line { from, to, progress: 0.0 }
    }

    /// The end point.
    pub fn target(&self) -> Vector3<f64> {
        self.to
    }

    /// Advances by one step of `dt` seconds from joints `at`; returns the new joints and
    /// whether the line is finished. `None` if a point is out of reach (checked beforehand
    /// with [`ArmModel::reaches_line`], so only rounding can get here).
    pub fn step(&mut self, arm: &ArmModel, at: Joints, dt: f64) -> Option<(Joints, bool)> {
        let length = (self.to - self.from).norm();
        if length < 1e-9 {
            self.progress = 1.0;
            return Some((arm.inverse(self.to)?, true));
        }
        let mut next = (self.progress + arm.linear_speed * dt / length).min(1.0);
        // Shrink the step until no joint exceeds its speed (the IK is smooth, so halving
        // converges quickly; eight halvings is a 256th of a step).
        for _ in 0..8 {
            let joints = arm.inverse(self.from.lerp(&self.to, next))?;
            if joint_distance(at, joints) <= arm.joint_speed * dt + 1e-12 {
                self.progress = next;
                return Some((joints, next >= 1.0));
            }
            next = self.progress + (next - self.progress) / 2.0;
        }
        let joints = arm.inverse(self.from.lerp(&self.to, next))?;
        self.progress = next;
        Some((joints, next >= 1.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arm() -> ArmModel {
        ArmModel { shoulder: Vector3::new(0.0, 0.0, 0.3), upper: 0.4, fore: 0.35, joint_speed: 2.0, linear_speed: 0.5 }
    }

    #[test]
    fn inverse_then_forward_is_the_identity_within_reach() {
        let arm = arm();
        for &(x, y, z) in &[(0.3, 0.1, 0.05), (-0.2, 0.4, 0.3), (0.5, -0.3, 0.0), (0.1, 0.05, 0.6)] {
            let target = Vector3::new(x, y, z);
            let joints = arm.inverse(target).expect("within reach");
            assert!((arm.forward(joints) - target).norm() < 1e-9, "{target:?}");
        }
    }

    #[test]
    fn points_beyond_the_links_are_out_of_reach() {
        let arm = arm();
        assert!(arm.inverse(Vector3::new(0.8, 0.0, 0.3)).is_none(), "0.8 m away, links 0.75 m");
        assert!(arm.inverse(Vector3::new(0.04, 0.0, 0.3)).is_none(), "inside the inner limit");
        assert!(!arm.reaches_line(Vector3::new(0.3, 0.0, 0.1), Vector3::new(0.9, 0.0, 0.1)));
    }

    #[test]
    fn a_line_respects_the_joint_speed_and_ends_on_target() {
        let arm = arm();
        let (from, to) = (Vector3::new(0.4, -0.3, 0.2), Vector3::new(-0.3, 0.4, 0.2));
        let mut joints = arm.inverse(from).unwrap();
        let mut line = Line::new(from, to);
        let dt = 0.01;
        let mut steps = 0;
        loop {
            let (next, done) = line.step(&arm, joints, dt).expect("reachable");
            assert!(joint_distance(joints, next) <= arm.joint_speed * dt + 1e-9);
            let moved = (arm.forward(next) - arm.forward(joints)).norm();
            assert!(moved <= arm.linear_speed * dt + 1e-9, "moved {moved}");
            joints = next;
            steps += 1;
            if done {
                break;
            }
            assert!(steps < 10_000, "never arrives");
        }
        assert!((arm.forward(joints) - to).norm() < 1e-9);
        // 0.99 m at 0.5 m/s is at least 198 steps; the yaw limit makes it slower still.
        assert!(steps >= 198, "{steps} steps");
    }
}
