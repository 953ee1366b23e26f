//! The instruction set, defined once.
//!
//! [`instructions!`] takes the table at the bottom of this file (opcode, mnemonic, operands)
//! and derives from it the [`Instr`] enum, its encoder, its decoder, the verifier's operand
//! checks and the disassembler's operand listing, so the five can never disagree. Opcode
//! numbers are append-only: a new node kind gets a new number and a new format version.

use super::operand::{Check, Delay, Effect, EventId, ImportId, MaxTime, NodeRef, Operand, Time, Value};
use super::reader::Reader;
use super::{Context, LoadError};

macro_rules! instructions {
    ($(
        $(#[$doc:meta])*
        $name:ident = $code:literal, $mnemonic:literal {
            $( $(#[$field_doc:meta])* $field:ident : $ty:ty ),* $(,)?
        }
    )*) => {
        /// One node of the behaviour tree, as the bytecode stores it.
        #[derive(Clone, Debug, PartialEq, Eq)]
        #[non_exhaustive]
        pub enum Instr {
            $(
                $(#[$doc])*
                $name {
                    $( $(#[$field_doc])* $field: $ty, )*
                },
            )*
        }

        impl Instr {
            /// Every opcode with its mnemonic, in opcode order.
            pub const OPCODES: &'static [(u8, &'static str)] = &[$(($code, $mnemonic)),*];

            /// This node's opcode.
            pub fn opcode(&self) -> u8 {
                match self {
                    $(Instr::$name { .. } => $code,)*
                }
            }

            /// This node's mnemonic, as the disassembler prints it.
            pub fn mnemonic(&self) -> &'static str {
                match self {
                    $(Instr::$name { .. } => $mnemonic,)*
                }
            }

            #[cfg(feature = "encode")]
            /// Appends the encoded node: its opcode, then each operand in table order.
            /// `offsets` turns child node indices into code offsets.
            pub(crate) fn encode(&self, out: &mut Vec<u8>, offsets: &[u32]) {
                out.push(self.opcode());
                match self {
                    $(Instr::$name { $($field),* } => {
                        $( $field.encode(out, offsets); )*
                    })*
                }
            }

            /// Decodes one node at the reader's position; child references stay code offsets.
            pub(crate) fn decode(reader: &mut Reader<'_>) -> Result<Instr, LoadError> {
                let at = reader.position();
                match reader.u8()? {
                    $($code => Ok(Instr::$name { $($field: <$ty as Operand>::decode(reader)?,)* }),)*
                    other => Err(LoadError::new(at, super::LoadErrorKind::UnknownOpcode(other))),
                }
            }

            /// Checks every operand against the program's tables (indices in range, child
            /// references on node starts, turned into node indices).
            pub(crate) fn check(&mut self, cx: &Context, at: usize) -> Result<(), LoadError> {
                match self {
                    $(Instr::$name { $($field),* } => {
                        $( $field.check(cx, at)?; )*
                        Ok(())
                    })*
                }
            }

            /// The operands as `(name, text)` pairs for the disassembler.
            #[cfg(feature = "disasm")]
            pub(crate) fn operands(&self, names: &dyn super::operand::Names) -> Vec<(&'static str, String)> {
                match self {
                    $(Instr::$name { $($field),* } => {
                        vec![$( (stringify!($field), $field.show(names)) ),*]
                    })*
                }
            }
        }
    };
}

instructions! {
    /// Ticks its children in order; a child's Success moves on to the next in the same tick,
    /// Running or Failure is the node's status. Success when every child has succeeded.
    Sequence = 0x01, "seq" {
        /// The children, in order.
        children: Vec<NodeRef>,
    }
    /// Ticks every child that has not yet succeeded, in order. Failure as soon as one fails;
    /// Success when all have succeeded; Running otherwise.
    Parallel = 0x02, "par" {
        /// The children.
        children: Vec<NodeRef>,
    }
    /// Waits for synchronisation: Success once every listed event has happened and the
    /// given time has passed since it; Running before.
    Wait = 0x03, "wait" {
        /// The events to wait for, each with the least time after it.
        after: Vec<Delay>,
    }
    /// Starts a durative action: checks its start conditions on the blackboard, applies its
    /// start effects, starts it on the host and records its event. Success once started;
    /// Failure when a condition fails or the host refuses.
    Start = 0x10, "start" {
        /// The event this node records (the snap action's time point).
        event: EventId,
        /// The host action.
        import: ImportId,
        /// Its ground arguments.
        args: Vec<Value>,
        /// The least duration; the end waits for it.
        min: Time,
        /// The greatest duration; running longer fails the end node.
        max: MaxTime,
        /// The start conditions.
        check: Check,
        /// The start effects, in order.
        effects: Vec<Effect>,
    }
    /// Ends a durative action: polls the host until the action started by `start` reports
    /// back and its least duration has passed, then checks the end conditions, applies the
    /// end effects and records its event. Failure when the host reports failure, the action
    /// overruns its greatest duration, or a condition fails.
    End = 0x11, "end" {
        /// The event this node records.
        event: EventId,
        /// The event of the start node whose action this ends.
        start: EventId,
        /// The end conditions.
        check: Check,
        /// The end effects, in order.
        effects: Vec<Effect>,
    }
    /// An instantaneous action: checks its conditions, starts it on the host, waits for the
    /// host to report back, then applies its effects and records its event.
    Act = 0x12, "act" {
        /// The event this node records.
        event: EventId,
        /// The host action.
        import: ImportId,
        /// Its ground arguments.
        args: Vec<Value>,
        /// Its conditions.
        check: Check,
        /// Its effects, in order.
        effects: Vec<Effect>,
    }
}
