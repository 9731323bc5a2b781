//! Threads for a module built with WebAssembly's shared memory (`+atomics`): a rayon pool whose
//! threads are Web Workers started by the host, each running this same module on the same
//! memory with a stack and thread-local storage of its own.
//!
//! ```text
//! host: n = splineskin_threads_start(k)       rayon asks the host for k − 1 threads: the import
//!                                              splineskin.spawn_thread(builder) is called k − 1 times
//!       for each builder b:
//!         s = splineskin_thread_memory(STACK, tls_size, tls_align)   (stack top, then TLS block)
//!         a worker instantiates the module on the same memory, sets __stack_pointer = s.stack_top,
//!         calls __wasm_init_tls(s.tls), then splineskin_thread_run(b), which never returns
//! ```
//!
//! The thread that calls `splineskin_threads_start` is the pool's first thread
//! (`use_current_thread`): a parallel loop it starts runs on it and on the others. Without
//! `+atomics` the module has no shared memory and this file compiles to nothing: rayon then runs
//! everything on the calling thread.

use std::alloc::Layout;

#[link(wasm_import_module = "splineskin")]
extern "C" {
    #[link_name = "spawn_thread"]
    fn host_spawn_thread(builder: usize);
}

/// Builds a rayon pool of `threads` threads, the caller and `threads − 1` the host starts
/// through its `spawn_thread` import; returns the number of threads, or 0 when the caller
/// already belongs to a pool.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_threads_start(threads: usize) -> usize {
    let threads = threads.max(1);
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .use_current_thread()
        .spawn_handler(|thread| {
            let builder = Box::into_raw(Box::new(thread)) as usize;
            // SAFETY: an imported function taking a number; the host hands it back to
            // `splineskin_thread_run` exactly once.
            unsafe { host_spawn_thread(builder) };
            Ok(())
        })
        .build()
        .map_or(0, |pool| {
            // The pool lives as long as the module. It is not rayon's global pool, whose
            // `build_global` waits until every thread runs: the host starts them only after
            // this returns. The caller being one of its threads, the parallel loops it starts
            // run on this pool all the same.
            std::mem::forget(pool);
            threads
        })
}

/// Allocates a thread's stack (`stack` bytes) and thread-local block (`tls_size` bytes aligned
/// to `tls_align`), never freed (a pool's threads live as long as the module); returns the
/// stack's top (stacks grow down), and the block's address in the output buffer's first slot.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_thread_memory(
    stack: usize,
    tls_size: usize,
    tls_align: usize,
) -> usize {
    let stack = Layout::from_size_align(stack.max(1 << 16), 16).expect("a stack's layout");
    let tls = Layout::from_size_align(tls_size.max(1), tls_align.max(1)).expect("a TLS layout");
    // SAFETY: both layouts have a non-zero size.
    let (stack_base, tls_base) = unsafe { (std::alloc::alloc(stack), std::alloc::alloc(tls)) };
    crate::OUTPUT.with_borrow_mut(|o| {
        o.clear();
        o.push(tls_base as usize as f64);
    });
    stack_base as usize + stack.size()
}

/// Runs the pool's thread `builder` (from `spawn_thread`) on the calling Web Worker: returns
/// only when the pool ends, which it does not.
#[allow(unsafe_code)]
#[no_mangle]
pub extern "C" fn splineskin_thread_run(builder: usize) {
    // SAFETY: `builder` came from `Box::into_raw` in `splineskin_threads_start` and the host
    // passes each one here once.
    let thread = unsafe { Box::from_raw(builder as *mut rayon::ThreadBuilder) };
    thread.run();
}
