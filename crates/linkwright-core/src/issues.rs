//! A bounded list of problems: the first ones in full, and how many more there are.
//!
//! Every validation (of a scene, a design file) answers with an [`IssueList`], so the answer to a
//! file that repeats one mistake a hundred thousand times stays a screenful, and the work of wording
//! the problems past the bound is skipped.

use std::ops::Deref;

/// The most problems a validation lists in full. A person fixing a file reads the first screenful and
/// fixes those before reading on; no reference scene, example or engine design comes near it, and a
/// file that repeats one mistake (a 1 MB scene naming a missing pose 340,000 times) is answered in
/// under 10 kB where the whole list would be tens of megabytes (the `linkwright` test
/// `a_mistake_repeated_340000_times_gets_a_short_answer`).
pub const MAX_LISTED_ISSUES: usize = 50;

/// The first [`MAX_LISTED_ISSUES`] problems found, in the order found, and how many more there were.
/// It reads as a slice of the listed ones; [`IssueList::total`] counts them all.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct IssueList<T> {
    listed: Vec<T>,
    more: usize,
}

impl<T> Default for IssueList<T> {
    fn default() -> Self {
        IssueList { listed: Vec::new(), more: 0 }
    }
}

impl<T> IssueList<T> {
    /// An empty list.
    pub fn new() -> Self {
        IssueList::default()
    }

    /// The problems listed in full (at most [`MAX_LISTED_ISSUES`]).
    pub fn listed(&self) -> &[T] {
        &self.listed
    }

    /// How many problems were found beyond the listed ones.
    pub fn more(&self) -> usize {
        self.more
    }

    /// How many problems were found, listed or not.
    pub fn total(&self) -> usize {
        self.listed.len() + self.more
    }

    /// Whether no problem was found.
    pub fn is_empty(&self) -> bool {
        self.total() == 0
    }

    /// Whether the list holds [`MAX_LISTED_ISSUES`] already, so a new problem is only counted.
    pub fn is_full(&self) -> bool {
        self.listed.len() >= MAX_LISTED_ISSUES
    }

    /// Adds a problem: listed while there is room, counted after.
    pub fn push(&mut self, issue: T) {
        self.push_with(|| issue);
    }

    /// Adds the problem `make` words, calling it only while there is room (wording costs more than
    /// counting).
    pub fn push_with(&mut self, make: impl FnOnce() -> T) {
        if self.is_full() {
            self.more += 1;
        } else {
            self.listed.push(make());
        }
    }

    /// Adds the problem `make` words, which outranks those for which `minor` holds: on a full list it
    /// takes the place of the last minor one (then counted among the more), so an error is never
    /// crowded out by warnings. `make` is called only when the problem is listed.
    pub(crate) fn push_over_with(&mut self, make: impl FnOnce() -> T, minor: impl Fn(&T) -> bool) {
        if self.is_full() {
            self.more += 1;
            let Some(i) = self.listed.iter().rposition(minor) else { return };
            self.listed.remove(i);
        }
        self.listed.push(make());
    }

    /// The listed problems, giving up the count of the others.
    pub fn into_listed(self) -> Vec<T> {
        self.listed
    }
}

impl<T> Deref for IssueList<T> {
    type Target = [T];
    fn deref(&self) -> &[T] {
        &self.listed
    }
}

impl<T> IntoIterator for IssueList<T> {
    type Item = T;
    type IntoIter = std::vec::IntoIter<T>;
    fn into_iter(self) -> Self::IntoIter {
        self.listed.into_iter()
    }
}

impl<'a, T> IntoIterator for &'a IssueList<T> {
    type Item = &'a T;
    type IntoIter = std::slice::Iter<'a, T>;
    fn into_iter(self) -> Self::IntoIter {
        self.listed.iter()
    }
}

impl<T> FromIterator<T> for IssueList<T> {
    fn from_iter<I: IntoIterator<Item = T>>(iter: I) -> Self {
        let mut list = IssueList::new();
        for issue in iter {
            list.push(issue);
        }
        list
    }
}

impl<T> Extend<T> for IssueList<T> {
    fn extend<I: IntoIterator<Item = T>>(&mut self, iter: I) {
        for issue in iter {
            self.push(issue);
        }
    }
}

/// A list equals a vector when it lists exactly the vector's problems and counts no more.
impl<T: PartialEq> PartialEq<Vec<T>> for IssueList<T> {
    fn eq(&self, other: &Vec<T>) -> bool {
        self.more == 0 && self.listed == *other
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lists_the_first_problems_and_counts_the_rest_without_wording_them() {
        let mut worded = 0;
        let mut list = IssueList::new();
        for i in 0..1000 {
            list.push_with(|| {
                worded += 1;
                i
            });
        }
        assert_eq!((list.len(), list.more(), list.total()), (MAX_LISTED_ISSUES, 950, 1000));
        assert_eq!(worded, MAX_LISTED_ISSUES);
        assert_eq!(list.listed()[..3], [0, 1, 2]);
    }

    #[test]
    fn a_major_problem_takes_the_place_of_the_last_minor_one() {
        // Odd numbers are minor.
        let mut list: IssueList<i32> = (0..MAX_LISTED_ISSUES as i32).collect();
        list.push_over_with(|| 1000, |&i| i % 2 == 1);
        assert_eq!((list.len(), list.more()), (MAX_LISTED_ISSUES, 1));
        assert!(!list.contains(&(MAX_LISTED_ISSUES as i32 - 1)) && list.last() == Some(&1000));
        // With no minor one left, it is only counted.
        let mut list: IssueList<i32> = (0..MAX_LISTED_ISSUES as i32).map(|i| 2 * i).collect();
        list.push_over_with(|| 1000, |&i| i % 2 == 1);
        assert_eq!((list.more(), list.contains(&1000)), (1, false));
    }
}
