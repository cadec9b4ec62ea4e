//! Run-time selection of the AVX2 + FMA kernels: one detection, one macro.
//!
//! The portable build targets baseline x86-64 (SSE2), so the wide kernels are compiled
//! separately with `#[target_feature(enable = "avx2,fma")]` and chosen at run time, as faer
//! does. Every kernel is written once, generic over `const FUSED: bool` (whether `a b + c` is
//! a fused multiply-add, which without hardware FMA would be a slow software routine);
//! [`dispatch_avx2_fma!`] turns it into a public function that calls the `FUSED = true`
//! instance compiled for AVX2 + FMA when the CPU has them and the portable one otherwise.

/// Whether the CPU has AVX2 and FMA (cached by the standard library after the first call).
#[inline]
pub(crate) fn has_avx2_fma() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// `fn name[generics](args) -> ret => kernel[kernel generics]` defines `name`, which calls
/// `kernel::<kernel generics, true>` compiled for AVX2 + FMA when [`has_avx2_fma`], else
/// `kernel::<kernel generics, false>`. The kernel generics end with a comma.
macro_rules! dispatch_avx2_fma {
    (
        $(#[$attribute:meta])*
        $visibility:vis fn $name:ident [$($generics:tt)*] ($($argument:ident: $type:ty),* $(,)?)
            $(-> $return:ty)? => $kernel:ident [$($kernel_generics:tt)*]
    ) => {
        $(#[$attribute])*
        $visibility fn $name<$($generics)*>($($argument: $type),*) $(-> $return)? {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma")]
                unsafe fn fused<$($generics)*>($($argument: $type),*) $(-> $return)? {
                    $kernel::<$($kernel_generics)* true>($($argument),*)
                }
                if $crate::simd::has_avx2_fma() {
                    // SAFETY: the CPU supports the features `fused` is compiled for.
                    return unsafe { fused($($argument),*) };
                }
            }
            $kernel::<$($kernel_generics)* false>($($argument),*)
        }
    };
}

pub(crate) use dispatch_avx2_fma;
