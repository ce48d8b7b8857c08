//! The key per-address limits are counted under. An IPv4 host has one address, but an IPv6
//! host is normally given a whole /64 and may rotate through it freely (privacy addresses
//! change by themselves), so keying IPv6 limits on the full address would hand it a fresh
//! budget with every address. IPv6 sources are therefore keyed on their /64 prefix; IPv4 (and
//! IPv4-mapped IPv6) on the address.

use std::net::{IpAddr, Ipv6Addr};

/// The key of `ip` for every per-address limit.
pub fn source_key(ip: IpAddr) -> IpAddr {
    match ip.to_canonical() {
        IpAddr::V4(v4) => IpAddr::V4(v4),
        IpAddr::V6(v6) => {
            let prefix = v6.to_bits() & !((1u128 << 64) - 1);
            IpAddr::V6(Ipv6Addr::from_bits(prefix))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::admission::{Decision, Ledger, Refusal};
    use crate::limits::Limits;

    fn v6(s: &str) -> IpAddr {
        s.parse().unwrap()
    }

    #[test]
    fn ipv6_is_keyed_on_its_64_and_ipv4_on_its_address() {
        let one = source_key(v6("2001:db8:1:2:aaaa:bbbb:cccc:dddd"));
        assert_eq!(one, v6("2001:db8:1:2::"));
        assert_eq!(one, source_key(v6("2001:db8:1:2::1")));
        assert_ne!(one, source_key(v6("2001:db8:1:3::1")));
        assert_eq!(
            source_key(v6("192.0.2.7")),
            source_key(v6("::ffff:192.0.2.7"))
        );
        assert_ne!(source_key(v6("192.0.2.7")), source_key(v6("192.0.2.8")));
    }

    #[test]
    fn addresses_of_one_64_share_one_handshake_budget() {
        let limits = Limits::default();
        let mut ledger = Ledger::default();
        // Each attempt from a new address of the same /64.
        for i in 0..limits.handshakes_per_address() {
            let key = source_key(v6(&format!("2001:db8::{:x}", i + 1)));
            assert_eq!(ledger.decide(&limits, key, true), Decision::Admit);
            ledger.opened(key);
        }
        let next = source_key(v6("2001:db8::ffff:1"));
        assert_eq!(
            ledger.decide(&limits, next, true),
            Decision::Refuse(Refusal::AddressShare)
        );
        let elsewhere = source_key(v6("2001:db8:0:1::1"));
        assert_eq!(ledger.decide(&limits, elsewhere, true), Decision::Admit);
    }
}
