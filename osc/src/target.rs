//! Where OSC goes and what can go wrong on the way: the target's address without the network
//! ([`resolve`]: numeric addresses and `localhost`, names never looked up), a non-blocking UDP
//! socket of its family ([`socket_for`]), one send ([`send`]) and why a frame was not sent
//! ([`OscError`], a small code with advice).

use std::net::{IpAddr, Ipv4Addr, SocketAddr, UdpSocket};
use std::time::{SystemTime, UNIX_EPOCH};

/// Why a frame was not sent, kept as a small code so that the plugin's audio thread can copy it
/// and its editor turns it into text ([`OscError::text`]) on its own thread: nothing allocates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum OscError {
    /// The host is not a numeric IP address or `localhost` (names are never looked up).
    NotAnAddress = 1,
    /// No UDP socket could be opened (no network stack, or no free port).
    NoSocket = 2,
    /// The frame did not fit a packet (should not happen: report it).
    Encoding = 3,
    /// The OS found no route to the host (network down, wrong address).
    Unreachable = 4,
    /// The receiver's port is closed (nothing listens there).
    Refused = 5,
    /// The OS refused to send (a firewall, or a broadcast address).
    PermissionDenied = 6,
    /// Any other send error.
    Other = 7,
}

impl OscError {
    /// The error for a stored code (`None` for 0 or an unknown code).
    pub fn from_code(code: u8) -> Option<Self> {
        [
            Self::NotAnAddress,
            Self::NoSocket,
            Self::Encoding,
            Self::Unreachable,
            Self::Refused,
            Self::PermissionDenied,
            Self::Other,
        ]
        .into_iter()
        .find(|e| *e as u8 == code)
    }

    /// What went wrong and what to do.
    pub fn text(self) -> &'static str {
        match self {
            Self::NotAnAddress => {
                "the host is not an IP address: enter a numeric address (e.g. 192.168.1.20) or localhost"
            }
            Self::NoSocket => "no UDP socket could be opened: check the network settings",
            Self::Encoding => "a frame did not fit an OSC packet (a bug: please report it)",
            Self::Unreachable => "no route to the host: check the address and that the network is up",
            Self::Refused => "nothing listens on that port: start the receiver or check the port",
            Self::PermissionDenied => "the system refused to send: check the firewall and the address",
            Self::Other => "sending failed: check the host and port",
        }
    }

    /// The kind of a failed send.
    pub fn of_send(e: &std::io::Error) -> Self {
        use std::io::ErrorKind;
        match e.kind() {
            ErrorKind::ConnectionRefused => Self::Refused,
            ErrorKind::PermissionDenied => Self::PermissionDenied,
            ErrorKind::HostUnreachable | ErrorKind::NetworkUnreachable | ErrorKind::NetworkDown => {
                Self::Unreachable
            }
            _ => Self::Other,
        }
    }
}

/// The target's address, without the network: a numeric IPv4 or IPv6 address (brackets
/// allowed) or `localhost` (127.0.0.1). Host names are not resolved: a DNS lookup can block for
/// minutes, and a plugin's worker stuck in one would hold up unloading the plugin (which joins
/// it); the CLI and the app take the same hosts as the plugin.
pub fn resolve(host: &str, port: u16) -> Option<SocketAddr> {
    let host = host.trim();
    let ip: IpAddr = if host.eq_ignore_ascii_case("localhost") {
        Ipv4Addr::LOCALHOST.into()
    } else {
        host.trim_start_matches('[')
            .trim_end_matches(']')
            .parse()
            .ok()?
    };
    Some(SocketAddr::new(ip, port))
}

/// A non-blocking UDP socket of the address family of `addr`.
pub fn socket_for(addr: &SocketAddr) -> Option<UdpSocket> {
    let socket = if addr.is_ipv4() {
        UdpSocket::bind(("0.0.0.0", 0))
    } else {
        UdpSocket::bind(("::", 0))
    }
    .ok()?;
    socket.set_nonblocking(true).ok()?;
    Some(socket)
}

/// Connects `socket` to `addr`, so that it hears the receiver's host answer that nothing
/// listens on the port (an unconnected socket is never told). Best effort: `false` when the
/// connect fails (no route yet, a broadcast address), and the socket stays unconnected.
pub fn connect(socket: &UdpSocket, addr: SocketAddr) -> bool {
    socket.connect(addr).is_ok()
}

/// Sends one packet to `addr` on `socket` (either missing: the error that says which), with
/// `send` when the socket is `connected` to it ([`connect`]; BSD and macOS refuse `send_to` on
/// a connected socket), else with `send_to`.
pub fn send(
    addr: Option<SocketAddr>,
    socket: Option<&UdpSocket>,
    connected: bool,
    packet: &[u8],
) -> Result<(), OscError> {
    let (addr, socket) = match (addr, socket) {
        (None, _) => return Err(OscError::NotAnAddress),
        (Some(_), None) => return Err(OscError::NoSocket),
        (Some(addr), Some(socket)) => (addr, socket),
    };
    if connected {
        socket.send(packet)
    } else {
        socket.send_to(packet, addr)
    }
    .map(|_| ())
    .map_err(|e| OscError::of_send(&e))
}

/// Seconds since the Unix epoch by the wall clock (the time tags' clock).
pub fn now_unix_s() -> f64 {
    SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_numeric_addresses_and_localhost_are_targets() {
        let at = |h: &str| resolve(h, 9000);
        assert_eq!(at("127.0.0.1"), Some("127.0.0.1:9000".parse().unwrap()));
        assert_eq!(at(" localhost "), Some("127.0.0.1:9000".parse().unwrap()));
        assert_eq!(at("LOCALHOST"), Some("127.0.0.1:9000".parse().unwrap()));
        assert_eq!(at("::1"), Some("[::1]:9000".parse().unwrap()));
        assert_eq!(at("[fe80::1]"), Some("[fe80::1]:9000".parse().unwrap()));
        for name in ["", "example.com", "my-avatar-pc", "10.0.0", "1.2.3.4:80"] {
            assert_eq!(at(name), None, "{name:?} is not an address");
        }
    }

    #[test]
    fn every_error_code_maps_back_and_has_advice() {
        assert_eq!(OscError::from_code(0), None, "0 is no error");
        assert_eq!(OscError::from_code(200), None);
        let mut seen = 0;
        for code in 1..=u8::MAX {
            if let Some(e) = OscError::from_code(code) {
                assert_eq!(e as u8, code);
                assert!(e.text().contains(':'), "{e:?} says what to do");
                seen += 1;
            }
        }
        assert_eq!(seen, 7, "each kind has its own code");
    }
}
