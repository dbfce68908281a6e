//! The boundary's errors: a failure's status and message ([`Failure`]), the thread's last
//! error (`LAST_ERROR`, kept without allocating for the lookups' messages), and [`guard`], which
//! runs an entry point's body under `catch_unwind` and records its failure.

use super::*;

/// The last error of a thread: a fixed message, one formatted into the thread's fixed buffer
/// (the lookups': no allocation), or a formatted one (opening and making handles).
pub(crate) enum Message {
    Static(&'static CStr),
    Inline,
    Owned(CString),
}

/// Room for a lookup's message, its NUL included: it names a value or two and their range.
pub(crate) const INLINE: usize = 240;

/// A message formatted into a fixed buffer, cut at a character boundary if it is longer, and
/// NUL-terminated by [`Inline::terminate`]. Rust messages hold no NUL.
pub(crate) struct Inline {
    pub(crate) bytes: [u8; INLINE],
    pub(crate) len: usize,
}

impl fmt::Write for Inline {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let mut take = s.len().min(INLINE - 1 - self.len);
        while !s.is_char_boundary(take) {
            take -= 1;
        }
        self.bytes[self.len..self.len + take].copy_from_slice(&s.as_bytes()[..take]);
        self.len += take;
        Ok(())
    }
}

impl Inline {
    /// Replaces the text by `message`, NUL-terminated.
    pub(crate) fn set(&mut self, message: fmt::Arguments<'_>) {
        self.len = 0;
        // `Inline` never fails; a `Display` that does leaves the text written so far.
        let _ = fmt::write(self, message);
        self.bytes[self.len] = 0;
    }
}

/// A thread's last error, and the buffer of its inline messages.
pub(crate) struct LastError {
    pub(crate) message: Message,
    pub(crate) inline: Inline,
}

thread_local! {
    pub(crate) static LAST_ERROR: RefCell<LastError> = const {
        RefCell::new(LastError {
            message: Message::Static(c"no error"),
            inline: Inline {
                bytes: [0; INLINE],
                len: 0,
            },
        })
    };
}

/// A failed call: its status code and message.
pub(crate) struct Failure {
    pub(crate) code: c_int,
    pub(crate) message: Message,
}

impl Failure {
    pub(crate) fn fixed(code: c_int, message: &'static CStr) -> Failure {
        Failure {
            code,
            message: Message::Static(message),
        }
    }

    pub(crate) fn text(code: c_int, message: String) -> Failure {
        // Rust messages hold no NUL; should one ever, keep the text before it.
        let bytes: Vec<u8> = message
            .into_bytes()
            .into_iter()
            .take_while(|&b| b != 0)
            .collect();
        let message = CString::new(bytes).map_or(Message::Static(c"error"), Message::Owned);
        Failure { code, message }
    }

    /// A failure whose message is formatted without allocating, straight into the thread's
    /// buffer ([`Inline`]), which [`guard`] then makes the last error: for the lookup paths,
    /// which never allocate, failing or not.
    #[cold]
    pub(crate) fn inline(code: c_int, message: fmt::Arguments<'_>) -> Failure {
        // `try_with`: during thread teardown the slot may be gone; the code still tells.
        let _ = LAST_ERROR.try_with(|slot| {
            if let Ok(mut slot) = slot.try_borrow_mut() {
                slot.inline.set(message);
            }
        });
        Failure {
            code,
            message: Message::Inline,
        }
    }

    pub(crate) fn null(name: &'static CStr) -> Failure {
        Failure::fixed(BSSRDF_ERROR_NULL_POINTER, name)
    }
}

/// The status of an [`EmbedError`].
pub(crate) fn embed_code(e: &EmbedError) -> c_int {
    match e {
        EmbedError::Format(FormatError::Io { .. }) => BSSRDF_ERROR_IO,
        EmbedError::Format(_) | EmbedError::Table { .. } | EmbedError::Sections { .. } => {
            BSSRDF_ERROR_FORMAT
        }
        EmbedError::NoMaterial { .. } | EmbedError::NoTable { .. } => BSSRDF_ERROR_NOT_FOUND,
        EmbedError::Medium { .. } => BSSRDF_ERROR_INVALID_ARGUMENT,
        EmbedError::AlbedoOutsideTable { .. } => BSSRDF_ERROR_OUT_OF_RANGE,
    }
}

impl From<EmbedError> for Failure {
    fn from(e: EmbedError) -> Failure {
        Failure::text(embed_code(&e), e.to_string())
    }
}

/// Runs an entry point's body: catches panics, records failures in the thread's last error.
#[inline(always)]
pub(crate) fn guard(body: impl FnOnce() -> Result<(), Failure>) -> c_int {
    let failure = match catch_unwind(AssertUnwindSafe(body)) {
        Ok(Ok(())) => return BSSRDF_OK,
        Ok(Err(failure)) => failure,
        Err(_) => Failure::fixed(
            BSSRDF_ERROR_PANIC,
            c"internal error: bssrdf-zoo panicked (a bug; please report it); the call did nothing",
        ),
    };
    // `try_with`: during thread teardown the slot may be gone; the code still tells the caller.
    let _ = LAST_ERROR.try_with(|slot| {
        if let Ok(mut slot) = slot.try_borrow_mut() {
            slot.message = failure.message;
        }
    });
    failure.code
}
