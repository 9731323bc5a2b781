//! Errors as one line for people: an error and its causes, each said once.

/// `error` and its causes ([`std::error::Error::source`], outermost first) joined by ": ",
/// each cause added unless the text so far says it already (a message that repeats its
/// cause's text, as many do, is not followed by it again).
///
/// ```
/// use splineskin::errors::message_with_causes;
/// #[derive(Debug)]
/// struct Outer(std::io::Error);
/// impl std::fmt::Display for Outer {
///     fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
///         write!(f, "fish.svg: cannot read")
///     }
/// }
/// impl std::error::Error for Outer {
///     fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
///         Some(&self.0)
///     }
/// }
/// let e = Outer(std::io::Error::other("permission denied"));
/// assert_eq!(message_with_causes(&e), "fish.svg: cannot read: permission denied");
/// ```
pub fn message_with_causes(error: &dyn std::error::Error) -> String {
    let mut message = error.to_string();
    let mut cause = error.source();
    while let Some(e) = cause {
        let text = e.to_string();
        if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
        cause = e.source();
    }
    message
}
