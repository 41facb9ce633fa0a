//! Data a kernel can be driven over in contiguous chunks.

use std::ops::Range;

/// Data that can be cut into two contiguous parts: slices, index ranges and
/// tuples of equally long ones (the columns of one ECS table).
pub trait Split: Sized + Send {
    /// Number of items.
    fn len(&self) -> usize;
    /// True when there are no items.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The first `mid` items and the rest.
    fn split_at(self, mid: usize) -> (Self, Self);
}

impl<T: Sync> Split for &[T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        <[T]>::split_at(self, mid)
    }
}

impl<T: Send> Split for &mut [T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

impl Split for Range<usize> {
    fn len(&self) -> usize {
        self.end.saturating_sub(self.start)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let cut = self.start + mid;
        (self.start..cut, cut..self.end)
    }
}

macro_rules! impl_split_for_tuple {
    ($($column:ident . $index:tt),+) => {
        impl<$($column: Split),+> Split for ($($column,)+) {
            fn len(&self) -> usize {
                let len = self.0.len();
                $(debug_assert_eq!(self.$index.len(), len, "split columns differ in length");)+
                len
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                let halves = ($(self.$index.split_at(mid),)+);
                (($(halves.$index.0,)+), ($(halves.$index.1,)+))
            }
        }
    };
}

impl_split_for_tuple!(A.0, B.1);
impl_split_for_tuple!(A.0, B.1, C.2);
impl_split_for_tuple!(A.0, B.1, C.2, D.3);
impl_split_for_tuple!(A.0, B.1, C.2, D.3, E.4);
impl_split_for_tuple!(A.0, B.1, C.2, D.3, E.4, F.5);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tuples_split_in_lockstep() {
        let (a, b) = ([1, 2, 3, 4], [5, 6, 7, 8]);
        let (head, tail) = (a.as_slice(), 10..14).split_at(1);
        assert_eq!(head, (&a[..1], 10..11));
        assert_eq!(tail, (&a[1..], 11..14));
        assert_eq!((a.as_slice(), b.as_slice()).len(), 4);
    }
}
