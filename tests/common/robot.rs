//! URDF and MJCF robots read in the crate's two phases, describe then insert, in one call
//! for the tests that only need the inserted robot (or the error of either phase).

// the crate's `UrdfError` returned as its API returns it (128 bytes, clippy's bound)
#![allow(clippy::result_large_err)]

use rapier_kjoint::io::mjcf::MjcfRobot;
use rapier_kjoint::io::urdf::{UrdfError, UrdfOptions, UrdfRobot, UrdfRobotHandles};
use rapier_kjoint::rapier::prelude::*;
use rapier_kjoint::KjointSet;
use std::path::Path;

/// [`UrdfRobot::from_file`], then `insert` into `world` and `joints`.
pub fn insert_urdf_file(
    path: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobotHandles, UrdfError> {
    UrdfRobot::from_file(path, options)?.insert(world, joints)
}

/// [`UrdfRobot::from_str`] (meshes relative to the current directory), then `insert`.
pub fn insert_urdf_str(
    text: &str,
    file: &str,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobotHandles, UrdfError> {
    UrdfRobot::from_str(text, file, ".", options)?.insert(world, joints)
}

/// [`MjcfRobot::from_file`], then `insert`.
pub fn insert_mjcf_file(
    path: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobotHandles, UrdfError> {
    MjcfRobot::from_file(path, options)?.insert(world, joints)
}

/// [`MjcfRobot::from_str`] (`<include>` and meshes relative to `base_dir`), then `insert`.
pub fn insert_mjcf_str(
    text: &str,
    file: &str,
    base_dir: impl AsRef<Path>,
    world: &mut PhysicsWorld,
    joints: &mut KjointSet,
    options: &UrdfOptions,
) -> Result<UrdfRobotHandles, UrdfError> {
    MjcfRobot::from_str(text, file, base_dir, options)?.insert(world, joints)
}
