//! `rapier_network`: the rain scene on a server, its dents replicated over loopback TCP to two
//! clients — one there from the start, one that joins late from a snapshot — which rebuild the
//! bunny and the block bit for bit without running physics.
//!
//! Frames on the socket: the length as a LEB128 varint (one byte up to 127), then the bytes; the
//! first frame a client gets is the snapshot, the others are messages, and an empty frame ends
//! the stream.

use std::io::{Read, Write};
use std::net::{TcpListener, TcpStream};
use std::thread::JoinHandle;

use dentbend::dent::DentSettings;
use dentbend::mesh::{TriMesh, content_hash};
use dentbend::record::replication::{ReplicationClient, ReplicationServer};
use rapier3d::prelude::ColliderHandle;

use super::rain::{Rain, RainSettings, target_dent};

/// Wire id of the bunny.
pub const BUNNY_ID: u32 = 1;
/// Wire id of the block.
pub const BLOCK_ID: u32 = 2;
/// Wire id of the balls' mesh.
pub const BALL_SHAPE: u32 = 1;

/// The run's size.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NetworkSettings {
    /// The server's scene (its balls are rigid: the stream carries the bunny and the block).
    pub rain: RainSettings,
    /// Dents made before the second client joins.
    pub join_after_dents: usize,
}

impl Default for NetworkSettings {
    fn default() -> Self {
        let rain = RainSettings { steps: 420, balls: 192, waves: 8, wave_interval: 50, seed: 11, rigid_balls: true };
        Self { rain, join_after_dents: 100 }
    }
}

/// What a run measured.
#[derive(Debug, Clone, PartialEq)]
pub struct NetworkRun {
    /// Steps the server ran.
    pub steps: usize,
    /// Dents the server made (and the stream carried).
    pub dents: usize,
    /// Messages sent to the client there from the start.
    pub messages: usize,
    /// Bytes of those messages on the socket, frame lengths included.
    pub stream_bytes: usize,
    /// Dents made before the late client joined.
    pub hits_before_join: usize,
    /// The late client's snapshot, bytes.
    pub late_join_bytes: usize,
    /// The same snapshot with every mesh sent whole, bytes.
    pub full_mesh_bytes: usize,
    /// Whether both clients' bunny and block are bit-identical to the server's.
    pub clients_identical: bool,
    /// Content hashes of the server's bunny and block at the end.
    pub server_hashes: [u64; 2],
    /// Each client's.
    pub client_hashes: [[u64; 2]; 2],
}

/// What a client is given up front: the bodies' base meshes and settings, the ball's mesh.
#[derive(Clone)]
struct Assets {
    bodies: Vec<(u32, TriMesh, DentSettings)>,
    ball: TriMesh,
}

/// Runs the server and both clients.
///
/// # Errors
/// A scene, socket or replication error, as text.
pub fn run(settings: NetworkSettings) -> Result<NetworkRun, Box<dyn std::error::Error>> {
    let mut rain = Rain::new(settings.rain)?;
    let mut server = ReplicationServer::<ColliderHandle>::new();
    let assets = Assets {
        bodies: vec![
            (BUNNY_ID, rain.initial[&rain.bunny].clone(), target_dent()),
            (BLOCK_ID, rain.initial[&rain.block].clone(), target_dent()),
        ],
        ball: rain.ball_mesh().clone(),
    };
    for (handle, (id, mesh, s)) in [rain.bunny, rain.block].into_iter().zip(&assets.bodies) {
        server.track(handle, *id, mesh, s)?;
    }
    server.add_projectile(BALL_SHAPE, &assets.ball)?;

    let listener = TcpListener::bind("127.0.0.1:0")?;
    let address = listener.local_addr()?;
    let connect = |assets: Assets| -> JoinHandle<Result<ClientEnd, String>> {
        std::thread::spawn(move || client(address, assets).map_err(|e| e.to_string()))
    };
    let early = connect(assets.clone());
    let (mut early_socket, _) = listener.accept()?;
    let meshes = |rain: &Rain, h| rain.adapter.dentables.mesh(h).cloned();
    send(&mut early_socket, &server.snapshot(|h| rain.adapter.dentables.mesh(h))?.bytes)?;

    let mut late: Option<(JoinHandle<Result<ClientEnd, String>>, TcpStream)> = None;
    let (mut dents, mut messages, mut stream_bytes) = (0, 0, 0);
    let (mut hits_before_join, mut late_join_bytes, mut full_mesh_bytes) = (0, 0, 0);
    for _ in 0..settings.rain.steps {
        let report = rain.step()?;
        dents += report.dents.len();
        let dentables = &rain.adapter.dentables;
        if let Some(message) = server.message(
            &report.dents,
            report.fractures.iter().map(|b| &b.fracture),
            |h| dentables.mesh(h),
            |h| dentables.surface(h),
        )? {
            stream_bytes += send(&mut early_socket, &message)?;
            messages += 1;
            if let Some((_, socket)) = late.as_mut() {
                send(socket, &message)?;
            }
        }
        if late.is_none() && dents >= settings.join_after_dents {
            let handle = connect(assets.clone());
            let (mut socket, _) = listener.accept()?;
            let snapshot = server.snapshot(|h| rain.adapter.dentables.mesh(h))?;
            send(&mut socket, &snapshot.bytes)?;
            (hits_before_join, late_join_bytes, full_mesh_bytes) =
                (dents, snapshot.bytes.len(), snapshot.full_mesh_bytes);
            late = Some((handle, socket));
        }
    }
    let server_hashes = [rain.bunny, rain.block].map(|h| meshes(&rain, h).map_or(0, |m| content_hash(&m)));
    send(&mut early_socket, &[])?;
    let early = early.join().map_err(|_| "the first client panicked")??;
    let (late_handle, mut late_socket) = late.ok_or("the late client never joined: too few dents")?;
    send(&mut late_socket, &[])?;
    let late = late_handle.join().map_err(|_| "the late client panicked")??;
    let client_hashes = [early.hashes, late.hashes];
    Ok(NetworkRun {
        steps: settings.rain.steps,
        dents,
        messages,
        stream_bytes,
        hits_before_join,
        late_join_bytes,
        full_mesh_bytes,
        clients_identical: client_hashes.iter().all(|h| *h == server_hashes),
        server_hashes,
        client_hashes,
    })
}

/// What a client ended with.
struct ClientEnd {
    hashes: [u64; 2],
}

/// A client: connects, joins from the first frame, applies every message until the empty frame.
fn client(address: std::net::SocketAddr, assets: Assets) -> Result<ClientEnd, Box<dyn std::error::Error>> {
    let mut socket = TcpStream::connect(address)?;
    let mut replica = ReplicationClient::new();
    for (id, mesh, s) in assets.bodies {
        replica.add_body(id, mesh, &s)?;
    }
    replica.add_projectile(BALL_SHAPE, assets.ball)?;
    replica.join(&receive(&mut socket)?)?;
    loop {
        let frame = receive(&mut socket)?;
        if frame.is_empty() {
            break;
        }
        replica.apply(&frame)?;
    }
    let hash = |id| replica.mesh(id).map_or(0, content_hash);
    Ok(ClientEnd { hashes: [hash(BUNNY_ID), hash(BLOCK_ID)] })
}

/// Writes one frame; returns its bytes on the socket.
fn send(socket: &mut TcpStream, bytes: &[u8]) -> std::io::Result<usize> {
    let mut frame = Vec::with_capacity(bytes.len() + 5);
    let mut length = bytes.len() as u64;
    loop {
        let low = (length & 0x7f) as u8;
        length >>= 7;
        frame.push(if length == 0 { low } else { low | 0x80 });
        if length == 0 {
            break;
        }
    }
    frame.extend_from_slice(bytes);
    socket.write_all(&frame)?;
    Ok(frame.len())
}

/// Most bytes one frame may declare (a snapshot of large meshes fits well within).
const MAX_FRAME: u64 = 256 << 20;

/// Reads one frame.
fn receive(socket: &mut TcpStream) -> std::io::Result<Vec<u8>> {
    let invalid = |what: String| std::io::Error::new(std::io::ErrorKind::InvalidData, what);
    let mut length = 0u64;
    for shift in (0..35).step_by(7) {
        let mut byte = [0u8; 1];
        socket.read_exact(&mut byte)?;
        length |= u64::from(byte[0] & 0x7f) << shift;
        if byte[0] & 0x80 == 0 {
            if length > MAX_FRAME {
                return Err(invalid(format!("a frame of {length} bytes")));
            }
            let mut bytes = vec![0; length as usize];
            socket.read_exact(&mut bytes)?;
            return Ok(bytes);
        }
    }
    Err(invalid("a frame length longer than 5 bytes".into()))
}
