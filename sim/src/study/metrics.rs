//! How far a method's result is from the event-based reference.

use super::trace::{Contact, Trace};

/// How many collisions and pockets from the start must agree for a sequence to match.
pub const SEQUENCE_LEN: usize = 10;

/// The comparison of one shot against the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// Mean and largest distance between final positions over the balls (mm).
    pub mean_mm: f64,
    pub max_mm: f64,
    /// The first `SEQUENCE_LEN` collisions and pockets are the same, in the same order.
    pub sequence_matches: bool,
    /// The same balls were pocketed.
    pub pockets_match: bool,
}

/// Compares `trace` with the reference `reference` (same shot, same balls).
pub fn compare(reference: &Trace, trace: &Trace) -> Comparison {
    let n = reference.finals.len().min(trace.finals.len()).max(1);
    let dists: Vec<f64> = reference
        .finals
        .iter()
        .zip(&trace.finals)
        .map(|(a, b)| (*a - *b).length() * 1e3)
        .collect();
    let mean_mm = dists.iter().sum::<f64>() / n as f64;
    let max_mm = dists.iter().copied().fold(0.0, f64::max);
    Comparison {
        mean_mm,
        max_mm,
        sequence_matches: head(&reference.contacts) == head(&trace.contacts),
        pockets_match: reference.pocketed() == trace.pocketed(),
    }
}

fn head(contacts: &[Contact]) -> &[Contact] {
    &contacts[..contacts.len().min(SEQUENCE_LEN)]
}

/// Did the method see the collision of balls `a` and `b` at all?
pub fn saw_collision(trace: &Trace, a: u16, b: u16) -> bool {
    trace.contacts.contains(&Contact::Balls(a.min(b), a.max(b)))
}

/// The first ball–ball collision, if any.
pub fn first_collision(trace: &Trace) -> Option<Contact> {
    trace
        .contacts
        .iter()
        .copied()
        .find(|c| matches!(c, Contact::Balls(..)))
}

/// The median of `values` (NaN for none).
pub fn median(values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        0.5 * (v[m - 1] + v[m])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec2;

    fn trace(contacts: Vec<Contact>, finals: &[[f64; 2]], pockets: Vec<Option<u8>>) -> Trace {
        Trace {
            contacts,
            finals: finals.iter().map(|p| DVec2::from_array(*p)).collect(),
            pockets,
        }
    }

    #[test]
    fn identical_traces_match_with_zero_error() {
        let t = trace(
            vec![Contact::Balls(0, 1), Contact::Pocket(1, 2)],
            &[[0.1, 0.2], [0.5, 0.5]],
            vec![None, Some(2)],
        );
        let c = compare(&t, &t);
        assert_eq!(c.mean_mm, 0.0);
        assert!(c.sequence_matches && c.pockets_match);
    }

    #[test]
    fn errors_are_mean_and_max_in_millimetres() {
        let a = trace(vec![], &[[0.0, 0.0], [1.0, 1.0]], vec![None, None]);
        let b = trace(vec![], &[[0.003, 0.004], [1.0, 1.0]], vec![None, None]);
        let c = compare(&a, &b);
        assert!(
            (c.max_mm - 5.0).abs() < 1e-9 && (c.mean_mm - 2.5).abs() < 1e-9,
            "{c:?}"
        );
    }

    #[test]
    fn only_the_first_ten_contacts_count_and_order_matters() {
        let base: Vec<Contact> = (0..10).map(Contact::Cushion).collect();
        let mut later = base.clone();
        later.push(Contact::Balls(0, 1));
        let mut swapped = base.clone();
        swapped.swap(3, 4);
        let finals = [[0.0, 0.0]];
        let r = trace(base, &finals, vec![None]);
        assert!(compare(&r, &trace(later, &finals, vec![None])).sequence_matches);
        assert!(!compare(&r, &trace(swapped, &finals, vec![None])).sequence_matches);
    }

    #[test]
    fn a_different_pocketed_set_does_not_match() {
        let finals = [[0.0, 0.0], [0.0, 0.0]];
        let a = trace(vec![], &finals, vec![None, Some(1)]);
        let b = trace(vec![], &finals, vec![None, Some(4)]);
        let c = trace(vec![], &finals, vec![Some(1), None]);
        assert!(compare(&a, &b).pockets_match, "same balls, other pocket");
        assert!(!compare(&a, &c).pockets_match);
    }

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
    }
}
