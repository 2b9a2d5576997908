//! The console on Windows. There the binary is a GUI program (`windows_subsystem = "windows"` in
//! `main.rs`), so a double-click opens the window and no console beside it; but a GUI program
//! gets no console of its own, so run from cmd or PowerShell its output would go nowhere.
//! `attach` joins the console of the program that started it (the terminal), for standard
//! output and error that were not redirected: with `> file` or through a pipe the handles are
//! already valid and are left as they are. Elsewhere it does nothing.

/// Join the parent's console where standard output or error has nowhere to go (Windows only).
pub fn attach() {
    #[cfg(windows)]
    imp::attach();
}

#[cfg(windows)]
mod imp {
    use windows_sys::Win32::Foundation::{HANDLE, INVALID_HANDLE_VALUE};
    use windows_sys::Win32::System::Console::{STD_ERROR_HANDLE, STD_HANDLE, STD_OUTPUT_HANDLE};

    fn usable(h: HANDLE) -> bool {
        !h.is_null() && h != INVALID_HANDLE_VALUE
    }

    pub(super) fn attach() {
        let ids: [STD_HANDLE; 2] = [STD_OUTPUT_HANDLE, STD_ERROR_HANDLE];
        let before = ids.map(ffi::std_handle);
        if before.into_iter().all(usable) {
            // Both redirected (a file, a pipe) or a console already: nothing to do.
            return;
        }
        if !ffi::attach_parent_console() {
            // Started by a double-click, from Explorer or the Start menu: no console to join.
            return;
        }
        for (id, old) in ids.into_iter().zip(before) {
            if usable(old) {
                // Keep a redirection (`> out.json` with the errors on the terminal).
                ffi::set_std_handle(id, old);
            } else if !usable(ffi::std_handle(id)) {
                if let Some(console) = ffi::open_console_output() {
                    ffi::set_std_handle(id, console);
                }
            }
        }
    }

    // Win32 FFI needs `unsafe`: kept to these four one-call wrappers, the crate's only unsafe.
    #[allow(unsafe_code)]
    mod ffi {
        use windows_sys::Win32::Foundation::{GENERIC_READ, GENERIC_WRITE, HANDLE};
        use windows_sys::Win32::Storage::FileSystem::{
            CreateFileW, FILE_ATTRIBUTE_NORMAL, FILE_SHARE_READ, FILE_SHARE_WRITE, OPEN_EXISTING,
        };
        use windows_sys::Win32::System::Console::{
            ATTACH_PARENT_PROCESS, AttachConsole, GetStdHandle, STD_HANDLE, SetStdHandle,
        };

        pub(super) fn std_handle(id: STD_HANDLE) -> HANDLE {
            // SAFETY: GetStdHandle takes one of the STD_* constants and only reads.
            unsafe { GetStdHandle(id) }
        }

        pub(super) fn set_std_handle(id: STD_HANDLE, h: HANDLE) {
            // SAFETY: `h` is a handle of this process (kept from before or just opened).
            unsafe { SetStdHandle(id, h) };
        }

        pub(super) fn attach_parent_console() -> bool {
            // SAFETY: no pointers; fails (returns 0) where the parent has no console.
            unsafe { AttachConsole(ATTACH_PARENT_PROCESS) != 0 }
        }

        /// The console's screen buffer, opened by its reserved name, where attaching left a
        /// standard handle empty.
        pub(super) fn open_console_output() -> Option<HANDLE> {
            let name: Vec<u16> = "CONOUT$".encode_utf16().chain([0]).collect();
            // SAFETY: `name` is a NUL-terminated UTF-16 string alive for the call; the
            // security attributes and template are null, as the API allows.
            let h = unsafe {
                CreateFileW(
                    name.as_ptr(),
                    GENERIC_READ | GENERIC_WRITE,
                    FILE_SHARE_READ | FILE_SHARE_WRITE,
                    std::ptr::null(),
                    OPEN_EXISTING,
                    FILE_ATTRIBUTE_NORMAL,
                    std::ptr::null_mut(),
                )
            };
            super::usable(h).then_some(h)
        }
    }
}
