//! What `rapier_network` shows: a Rapier server's dents, sent over loopback TCP, rebuild the
//! bunny and the block bit for bit on a client there from the start and on one that joined
//! late, at most 64 bytes a dent on the wire (frame lengths included), with a late join no
//! bigger than the meshes sent whole.

use dentbend_rapier::demo::network::{NetworkSettings, run};
use dentbend_rapier::demo::rain::RainSettings;

#[test]
fn clients_rebuild_the_servers_meshes_bit_for_bit_from_small_messages() {
    // The example's run: the late client joins after at least 100 dents.
    let settings = NetworkSettings::default();
    let r = run(settings).unwrap();
    assert!(
        r.hits_before_join >= 100 && r.hits_before_join < r.dents,
        "joined after {} of {}",
        r.hits_before_join,
        r.dents
    );
    assert!(r.clients_identical, "server {:x?}, clients {:x?}", r.server_hashes, r.client_hashes);
    let per_dent = r.stream_bytes as f64 / r.dents as f64;
    assert!(per_dent <= 64.0, "{per_dent:.1} bytes a dent");
    assert!(r.late_join_bytes <= r.full_mesh_bytes, "{} > {}", r.late_join_bytes, r.full_mesh_bytes);
    // A stream that carried nothing would leave the clients "identical" too.
    assert!(r.messages > 0 && r.dents > r.hits_before_join);
    // Another seed: still identical.
    let rain = RainSettings { seed: 5, ..settings.rain };
    let r = run(NetworkSettings { rain, ..settings }).unwrap();
    assert!(r.clients_identical, "seed 5: server {:x?}, clients {:x?}", r.server_hashes, r.client_hashes);
}
