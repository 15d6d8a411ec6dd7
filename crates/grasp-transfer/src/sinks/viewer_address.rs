//! Whether a live Rerun viewer or server listens where a recording is to be streamed
//! (`grasp transfer --rerun-connect`), checked before the run so that a wrong address is an
//! error with its fix, not a run that streams to nowhere.

/// Whether something listens at the host and port of the gRPC address `url`
/// (`rerun+http://HOST:PORT/proxy`), within two seconds.
pub fn reachable(url: &str) -> Result<(), String> {
    use std::net::{TcpStream, ToSocketAddrs};
    let rest = url.split_once("://").map_or(url, |(_, r)| r);
    let host_port = rest.split('/').next().unwrap_or(rest);
    let hint = "start a viewer with `rerun` (or a headless server with `rerun --save F.rrd`), or check the address";
    let addrs: Vec<_> = host_port
        .to_socket_addrs()
        .map_err(|e| format!("cannot resolve `{host_port}`: {e}; {hint}"))?
        .collect();
    let timeout = std::time::Duration::from_secs(2);
    match addrs
        .iter()
        .any(|a| TcpStream::connect_timeout(a, timeout).is_ok())
    {
        true => Ok(()),
        false => Err(format!(
            "no Rerun viewer or server listens at {host_port}; {hint}"
        )),
    }
}
