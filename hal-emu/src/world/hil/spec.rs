//! The robots in the loop of a run as `cimax arena --hil` names them: `qemu:N`,
//! `serial:PATH[@BAUD]`, `tcp:HOST:PORT`, `loopback:N` ([`HilSpec`]).

use std::path::PathBuf;
use std::str::FromStr;

use super::error::SpecError;
use super::transport::Transport;

/// The robots in the loop of a run, as `cimax arena --hil` names them.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum HilSpec {
    /// `qemu:N`: N QEMU robots.
    Qemu(usize),
    /// `serial:PATH[@BAUD]`: one board (115200 Bd by default).
    Serial(PathBuf, u32),
    /// `tcp:HOST:PORT`: one robot on a socket.
    Tcp(String),
    /// `loopback:N`: N robots in this process, over the link.
    Loopback(usize),
}

/// The default baud rate of `serial:PATH`: the Nucleo image's USART2.
pub const DEFAULT_BAUD: u32 = 115_200;

impl HilSpec {
    /// How many robots it brings.
    pub fn robots(&self) -> usize {
        match self {
            HilSpec::Qemu(n) | HilSpec::Loopback(n) => *n,
            HilSpec::Serial(..) | HilSpec::Tcp(_) => 1,
        }
    }

    /// Each robot's transport; QEMU robots boot `image`.
    pub fn transports(&self, image: &std::path::Path) -> Vec<Transport> {
        match self {
            HilSpec::Qemu(n) => vec![Transport::Qemu(image.to_path_buf()); *n],
            HilSpec::Loopback(n) => vec![Transport::InProcess; *n],
            HilSpec::Serial(p, b) => vec![Transport::Serial(p.clone(), *b)],
            HilSpec::Tcp(a) => vec![Transport::Tcp(a.clone())],
        }
    }
}

impl FromStr for HilSpec {
    type Err = SpecError;

    fn from_str(s: &str) -> Result<Self, SpecError> {
        let count = |n: &str, what: &'static str| -> Result<usize, SpecError> {
            match n.parse::<usize>() {
                Ok(k @ 1..=64) => Ok(k),
                _ => Err(SpecError::Count {
                    what,
                    n: n.to_string(),
                }),
            }
        };
        if let Some(n) = s.strip_prefix("qemu:") {
            return count(n, "qemu").map(HilSpec::Qemu);
        }
        if let Some(n) = s.strip_prefix("loopback:") {
            return count(n, "loopback").map(HilSpec::Loopback);
        }
        if let Some(rest) = s.strip_prefix("serial:") {
            let (path, baud) = match rest.rsplit_once('@') {
                Some((p, b)) => {
                    let baud = b.parse::<u32>().ok().filter(|&b| b > 0).ok_or_else(|| {
                        SpecError::Baud {
                            baud: b.to_string(),
                        }
                    })?;
                    (p, baud)
                }
                None => (rest, DEFAULT_BAUD),
            };
            if path.is_empty() {
                return Err(SpecError::NoPath);
            }
            return Ok(HilSpec::Serial(PathBuf::from(path), baud));
        }
        if let Some(addr) = s.strip_prefix("tcp:") {
            let ok = addr
                .rsplit_once(':')
                .is_some_and(|(h, p)| !h.is_empty() && p.parse::<u16>().is_ok());
            if !ok {
                return Err(SpecError::Address {
                    addr: addr.to_string(),
                });
            }
            return Ok(HilSpec::Tcp(addr.to_string()));
        }
        Err(SpecError::Unknown {
            spec: s.to_string(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs_parse_and_refuse_with_a_reason() {
        assert_eq!("qemu:4".parse(), Ok(HilSpec::Qemu(4)));
        assert_eq!("loopback:2".parse(), Ok(HilSpec::Loopback(2)));
        assert_eq!(
            "serial:/dev/ttyACM0".parse(),
            Ok(HilSpec::Serial("/dev/ttyACM0".into(), DEFAULT_BAUD))
        );
        assert_eq!(
            "serial:/dev/ttyACM0@9600".parse(),
            Ok(HilSpec::Serial("/dev/ttyACM0".into(), 9600))
        );
        assert_eq!(
            "tcp:127.0.0.1:4000".parse(),
            Ok(HilSpec::Tcp("127.0.0.1:4000".into()))
        );
        for (bad, why) in [
            ("qemu:0", "N from 1 to 64"),
            ("qemu:x", "N from 1 to 64"),
            ("serial:", "needs a path"),
            ("serial:/dev/x@fast", "no baud rate"),
            ("tcp:4000", "no host and port"),
            ("udp:1", "qemu:N, serial:PATH"),
        ] {
            let e = bad.parse::<HilSpec>().unwrap_err().to_string();
            assert!(e.contains(why), "{bad}: {e}");
        }
    }
}
