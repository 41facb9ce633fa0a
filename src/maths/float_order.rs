//! Floats as integers in the same order: for sorting keys (the sweep
//! order) and for searching over all floats in order (a grid's bounds).

/// Maps an f32 to a u32 with the same order (for all non-NaN values; −0
/// just below +0).
#[inline]
pub fn order_key(x: f32) -> u32 {
    let bits = x.to_bits();
    if bits & 0x8000_0000 != 0 {
        !bits
    } else {
        bits | 0x8000_0000
    }
}

/// The float with this [`order_key`].
#[inline]
pub fn from_order_key(key: u32) -> f32 {
    f32::from_bits(if key & 0x8000_0000 != 0 {
        key & 0x7fff_ffff
    } else {
        !key
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_key_preserves_float_order() {
        let xs = [-1e30f32, -5.0, -1.0, -0.0, 0.0, 1e-40, 1.0, 2.5, 1e30];
        for w in xs.windows(2) {
            assert!(order_key(w[0]) <= order_key(w[1]), "{} vs {}", w[0], w[1]);
        }
    }

    #[test]
    fn from_order_key_inverts_order_key() {
        let xs = [f32::MIN, -1e30, -5.0, -0.0, 0.0, 1e-40, 2.5, f32::MAX, f32::INFINITY];
        for x in xs {
            assert_eq!(from_order_key(order_key(x)).to_bits(), x.to_bits(), "{x}");
        }
    }
}
