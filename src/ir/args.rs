//! [`Args`]: the arguments of a HIR compound term, behind one thin pointer.
//!
//! `Box<[Term]>` is a fat pointer (address and length, 16 bytes), which made every
//! [`Term`] 24 bytes and a list cell (two terms) a 48-byte allocation that glibc's malloc
//! rounds up to a 64-byte chunk. `Args` keeps the count at the front of the allocation
//! instead: the pointer is 8 bytes, a term 16, and a list cell 8 + 2 x 16 = 40 bytes in a
//! 48-byte chunk. For a fact holding a list of a million items, massif counted 48,000,048
//! bytes of cells before and 40,000,040 after (64 and 48 MB in glibc's chunks, by the
//! rounding above); `kbc check` of it peaked at 115 MB before this and the iterative drop
//! below, 86 MB after (/usr/bin/time; see the closing notes of issue 24).
//!
//! This is the crate's only unsafe code. The invariants, which every function below keeps:
//! `ptr` points to an allocation made with [`Args::layout`]`(len)`, whose first 8 bytes hold
//! `len` (a `u64`) and whose next `len * size_of::<Term>()` bytes hold `len` initialised
//! terms, owned by this `Args`. Nothing else refers to the allocation.

use std::alloc::{Layout, alloc, dealloc, handle_alloc_error};
use std::fmt;
use std::ops::{Deref, DerefMut};
use std::ptr::NonNull;

use super::hir::Term;

/// The arguments of a compound term: a boxed slice of terms with its length stored in the
/// allocation, so the handle is one pointer. Reads as `[Term]` through `Deref`.
pub struct Args {
    ptr: NonNull<u64>,
}

// SAFETY: `Args` owns its terms as a `Box<[Term]>` would, and terms hold no shared state.
unsafe impl Send for Args {}
// SAFETY: as above; `&Args` gives only `&[Term]`.
unsafe impl Sync for Args {}

impl Args {
    /// The allocation for `len` terms: the length, then the terms (at offset 8, which is the
    /// alignment of a term).
    fn layout(len: usize) -> Layout {
        let header = Layout::new::<u64>();
        let items = Layout::array::<Term>(len).expect("an argument count that fits in memory");
        let (layout, offset) = header.extend(items).expect("an argument count that fits in memory");
        debug_assert_eq!(offset, size_of::<u64>(), "the terms start right after the length");
        layout.pad_to_align()
    }

    /// The arguments `items`, moved out of the iterator, which must yield exactly `len` of
    /// them (it is only given iterators of vectors and arrays, which do).
    fn from_exact(len: usize, mut items: impl Iterator<Item = Term>) -> Args {
        let layout = Args::layout(len);
        // SAFETY: the layout is never zero-sized (it holds the length).
        let raw = unsafe { alloc(layout) }.cast::<u64>();
        let Some(ptr) = NonNull::new(raw) else { handle_alloc_error(layout) };
        // SAFETY: the allocation has room for the length and `len` terms after it; each slot
        // is written once. Should the iterator end early or panic, the allocation and the
        // terms written so far leak, and no `Args` ever sees the unwritten slots.
        unsafe {
            let data = ptr.as_ptr().add(1).cast::<Term>();
            for i in 0..len {
                let item = items.next().expect("the iterator yields as many terms as it said");
                data.add(i).write(item);
            }
            ptr.as_ptr().write(len as u64);
        }
        Args { ptr }
    }

    /// The arguments as a vector (moved out, no copy of the terms themselves).
    pub fn into_vec(self) -> Vec<Term> {
        let len = self.len();
        let mut items = Vec::with_capacity(len);
        let this = std::mem::ManuallyDrop::new(self);
        // SAFETY: each initialised term is read (moved) out exactly once, then the
        // allocation is freed without dropping them again (`this` is never dropped).
        unsafe {
            let data = this.ptr.as_ptr().add(1).cast::<Term>();
            for i in 0..len {
                items.push(data.add(i).read());
            }
            dealloc(this.ptr.as_ptr().cast::<u8>(), Args::layout(len));
        }
        items
    }
}

impl Deref for Args {
    type Target = [Term];

    fn deref(&self) -> &[Term] {
        // SAFETY: by the invariant, the length is stored first and that many initialised
        // terms follow; the borrow of `self` keeps them alive and unaliased by `&mut`.
        unsafe {
            let len = self.ptr.as_ptr().read() as usize;
            std::slice::from_raw_parts(self.ptr.as_ptr().add(1).cast::<Term>(), len)
        }
    }
}

impl DerefMut for Args {
    fn deref_mut(&mut self) -> &mut [Term] {
        // SAFETY: as in `deref`, and `&mut self` makes the borrow unique.
        unsafe {
            let len = self.ptr.as_ptr().read() as usize;
            std::slice::from_raw_parts_mut(self.ptr.as_ptr().add(1).cast::<Term>(), len)
        }
    }
}

impl Drop for Args {
    /// Drops the terms without recursing on their depth: a list of a million items is a
    /// million cells nested in one another, and dropping each inside its parent's drop took
    /// a stack frame per cell (tens of MB of stack). The nested argument lists are detached
    /// first and dropped from a worklist, each with no compound left in it.
    fn drop(&mut self) {
        let mut nested = Vec::new();
        detach_nested(self, &mut nested);
        while let Some(mut args) = nested.pop() {
            detach_nested(&mut args, &mut nested);
        }
        let len = self.len();
        // SAFETY: the terms are initialised and owned here; after dropping them the
        // allocation is freed with the layout it was made with.
        unsafe {
            std::ptr::drop_in_place(&mut **self as *mut [Term]);
            dealloc(self.ptr.as_ptr().cast::<u8>(), Args::layout(len));
        }
    }
}

/// Moves the argument lists of `args`'s compound terms into `into`, leaving atoms in their
/// place.
fn detach_nested(args: &mut Args, into: &mut Vec<Args>) {
    for term in args.iter_mut() {
        if matches!(term, Term::Compound(..)) {
            if let Term::Compound(_, inner) = std::mem::replace(term, Term::Int(0)) {
                into.push(inner);
            }
        }
    }
}

impl Clone for Args {
    fn clone(&self) -> Args {
        Args::from_exact(self.len(), self.iter().cloned())
    }
}

impl PartialEq for Args {
    fn eq(&self, other: &Args) -> bool {
        **self == **other
    }
}

impl fmt::Debug for Args {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl From<Vec<Term>> for Args {
    fn from(items: Vec<Term>) -> Args {
        Args::from_exact(items.len(), items.into_iter())
    }
}

impl From<Box<[Term]>> for Args {
    fn from(items: Box<[Term]>) -> Args {
        Args::from(items.into_vec())
    }
}

impl<const N: usize> From<[Term; N]> for Args {
    fn from(items: [Term; N]) -> Args {
        Args::from_exact(N, items.into_iter())
    }
}

impl FromIterator<Term> for Args {
    fn from_iter<I: IntoIterator<Item = Term>>(items: I) -> Args {
        Args::from(items.into_iter().collect::<Vec<_>>())
    }
}

impl<'a> IntoIterator for &'a Args {
    type Item = &'a Term;
    type IntoIter = std::slice::Iter<'a, Term>;

    fn into_iter(self) -> Self::IntoIter {
        self.iter()
    }
}

#[cfg(test)]
mod tests {
    use super::Args;
    use crate::intern::Symbol;
    use crate::ir::hir::Term;

    fn sample(n: usize) -> Vec<Term> {
        (0..n)
            .map(|i| match i % 3 {
                0 => Term::Int(i as i64),
                1 => Term::Compound(Symbol(7), Args::from([Term::Atom(Symbol(i as u32)), Term::Float(0.5)])),
                _ => Term::Compound(Symbol(8), Args::from(Vec::new())),
            })
            .collect()
    }

    /// A term is two words, and a list cell's arguments fit a 48-byte malloc chunk.
    #[test]
    fn a_term_is_sixteen_bytes() {
        assert_eq!(size_of::<Term>(), 16);
        assert_eq!(Args::layout(2).size(), 40);
    }

    /// A list of a million items is dropped in a thread with 128 KB of stack: the drop does
    /// not recurse on the list's length (it did, and took tens of MB of stack).
    #[test]
    #[cfg_attr(miri, ignore = "a million allocations")]
    fn dropping_a_long_list_takes_no_stack() {
        let dropped = std::thread::Builder::new()
            .stack_size(128 * 1024)
            .spawn(|| {
                let mut list = Term::Atom(Symbol(0));
                for i in 0..1_000_000 {
                    list = Term::Compound(Symbol(1), Args::from([Term::Int(i), list]));
                }
                drop(list);
            })
            .expect("a thread")
            .join();
        assert!(dropped.is_ok());
    }

    /// Every way in and out keeps the terms, in order: from vectors, boxes, arrays and
    /// iterators, cloned, compared, written through `DerefMut` and moved back out.
    #[test]
    fn arguments_keep_their_terms() {
        for n in [0, 1, 2, 3, 17, 1000] {
            let items = sample(n);
            let args = Args::from(items.clone());
            assert_eq!(&*args, &items[..]);
            assert_eq!(args.len(), n);
            let mut copy = args.clone();
            assert_eq!(copy, args);
            assert_eq!(Args::from(items.clone().into_boxed_slice()), args);
            assert_eq!(items.iter().cloned().collect::<Args>(), args);
            if n > 0 {
                copy[n - 1] = Term::Atom(Symbol(99));
                assert_ne!(copy, args);
                assert_eq!(copy[n - 1], Term::Atom(Symbol(99)));
            }
            assert_eq!(args.into_vec(), items);
            assert_eq!(format!("{:?}", Args::from(items.clone())), format!("{items:?}"));
        }
    }
}
