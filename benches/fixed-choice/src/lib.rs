//! One non-inlined function per operation and type; `count.sh` disassembles them for
//! thumbv7em-none-eabihf and counts instructions.
#![no_std]

use fixed::types::I16F16;
use rbtrack::fixed::Q16;

#[inline(never)]
pub fn own_add(a: Q16, b: Q16) -> Q16 {
    a + b
}
#[inline(never)]
pub fn fixed_add(a: I16F16, b: I16F16) -> I16F16 {
    a.saturating_add(b)
}
#[inline(never)]
pub fn own_mul(a: Q16, b: Q16) -> Q16 {
    a * b
}
#[inline(never)]
pub fn fixed_mul(a: I16F16, b: I16F16) -> I16F16 {
    a.saturating_mul(b)
}
#[inline(never)]
pub fn own_div(a: Q16, b: Q16) -> Q16 {
    a / b
}
#[inline(never)]
pub fn fixed_div(a: I16F16, b: I16F16) -> I16F16 {
    if b == I16F16::ZERO {
        return I16F16::ZERO;
    }
    a.saturating_div(b)
}
#[inline(never)]
pub fn own_sqrt(a: Q16) -> Q16 {
    a.sqrt()
}
#[inline(never)]
pub fn fixed_sqrt(a: I16F16) -> I16F16 {
    if a <= I16F16::ZERO {
        return I16F16::ZERO;
    }
    a.sqrt()
}
