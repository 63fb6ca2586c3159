//! The kinematic tree of a [`Robot`]: links by name (a `HashMap`), each
//! link's parent joint and child joints, and the root — built in time linear
//! in the number of links and joints, refusing what is not one tree.

use super::error::UrdfError;
use super::robot::{Joint, Link, Robot};
use std::collections::HashMap;

/// How many root names an error lists at most.
const ROOTS_SHOWN: usize = 10;

/// A robot's links and joints as one tree: every joint names links that
/// exist, every link is the child of at most one joint, there is no cycle,
/// and exactly one link (the root) is no joint's child.
#[derive(Clone, Debug)]
pub struct Tree<'r> {
    robot: &'r Robot,
    index: HashMap<&'r str, usize>,
    /// Per joint: (parent link, child link).
    ends: Vec<(usize, usize)>,
    /// Per link: the joint whose child it is.
    parent: Vec<Option<usize>>,
    /// Per link: the joints whose parent it is, in file order.
    children: Vec<Vec<usize>>,
    root: usize,
}

impl<'r> Tree<'r> {
    /// The tree of `robot` (names already unique, as [`super::read_str`]
    /// ensures), or the first structural error: a joint naming a missing
    /// link, a link with two parent joints, a cycle, no or several roots.
    /// `path` names the file in errors.
    pub fn new(robot: &'r Robot, path: &str) -> Result<Self, UrdfError> {
        let index: HashMap<&str, usize> = robot
            .links
            .iter()
            .enumerate()
            .map(|(i, l)| (l.name.as_str(), i))
            .collect();
        let ends = joint_ends(robot, &index, path)?;
        let n = robot.links.len();
        let mut parent: Vec<Option<usize>> = vec![None; n];
        let mut children = vec![Vec::new(); n];
        for (j, &(p, c)) in ends.iter().enumerate() {
            if let Some(first) = parent[c] {
                return Err(UrdfError::TwoParents {
                    path: path.into(),
                    link: robot.links[c].name.clone(),
                    first: robot.joints[first].name.clone(),
                    second: robot.joints[j].name.clone(),
                });
            }
            parent[c] = Some(j);
            children[p].push(j);
        }
        let mut tree = Self {
            robot,
            index,
            ends,
            parent,
            children,
            root: 0,
        };
        tree.root = tree.only_root(path)?;
        Ok(tree)
    }

    /// The one root, after checking that every link is reached from a root
    /// (with one parent each, a link that is not lies on or below a cycle).
    fn only_root(&self, path: &str) -> Result<usize, UrdfError> {
        let roots: Vec<usize> = (0..self.parent.len())
            .filter(|&l| self.parent[l].is_none())
            .collect();
        let mut reached = vec![false; self.parent.len()];
        let mut stack = roots.clone();
        while let Some(l) = stack.pop() {
            reached[l] = true;
            stack.extend(self.children[l].iter().map(|&j| self.ends[j].1));
        }
        if let Some(l) = reached.iter().position(|r| !r) {
            return Err(self.cycle_above(l, path));
        }
        match roots.as_slice() {
            [r] => Ok(*r),
            _ => Err(UrdfError::Roots {
                path: path.into(),
                count: roots.len(),
                roots: roots
                    .iter()
                    .take(ROOTS_SHOWN)
                    .map(|&r| self.robot.links[r].name.clone())
                    .collect(),
            }),
        }
    }

    /// The cycle found by following parents up from link `l`, which no root
    /// reaches.
    fn cycle_above(&self, l: usize, path: &str) -> UrdfError {
        // step at which each link was first met going up
        let mut met = vec![usize::MAX; self.parent.len()];
        let (mut link, mut step) = (l, 0);
        while met[link] == usize::MAX {
            met[link] = step;
            step += 1;
            match self.parent[link] {
                Some(j) => link = self.ends[j].0,
                None => break, // not so: no root reaches `l`
            }
        }
        let joint =
            self.parent[link].map_or_else(String::new, |j| self.robot.joints[j].name.clone());
        UrdfError::Cycle {
            path: path.into(),
            joint,
            link: self.robot.links[link].name.clone(),
            length: step - met[link].min(step),
        }
    }

    /// The robot.
    pub fn robot(&self) -> &'r Robot {
        self.robot
    }

    /// The root link's index in [`Robot::links`].
    pub fn root(&self) -> usize {
        self.root
    }

    /// The index of the link named `name`.
    pub fn link_index(&self, name: &str) -> Option<usize> {
        self.index.get(name).copied()
    }

    /// Link `i`.
    pub fn link(&self, i: usize) -> &'r Link {
        &self.robot.links[i]
    }

    /// The index of the joint whose child link `i` is (`None`: the root).
    pub fn parent_joint(&self, i: usize) -> Option<usize> {
        self.parent[i]
    }

    /// The indices of the joints whose parent link `i` is, in file order.
    pub fn child_joints(&self, i: usize) -> &[usize] {
        &self.children[i]
    }

    /// Joint `j`.
    pub fn joint(&self, j: usize) -> &'r Joint {
        &self.robot.joints[j]
    }

    /// Joint `j`'s child link index.
    pub fn child_link(&self, j: usize) -> usize {
        self.ends[j].1
    }

    /// Joint `j`'s parent link index.
    pub fn parent_link(&self, j: usize) -> usize {
        self.ends[j].0
    }
}

/// Every joint's (parent, child) link indices, or the first joint that
/// names a link that does not exist.
fn joint_ends(
    robot: &Robot,
    index: &HashMap<&str, usize>,
    path: &str,
) -> Result<Vec<(usize, usize)>, UrdfError> {
    let find = |j: &Joint, role: &'static str, name: &str| {
        index
            .get(name)
            .copied()
            .ok_or_else(|| UrdfError::MissingLink {
                path: path.into(),
                joint: j.name.clone(),
                role,
                link: name.to_string(),
            })
    };
    robot
        .joints
        .iter()
        .map(|j| Ok((find(j, "parent", &j.parent)?, find(j, "child", &j.child)?)))
        .collect()
}
