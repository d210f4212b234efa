"""Ship each member of an ensemble denoiser as its own denoiser folder.

Usage: ``python bench/rounds/r24/split_quint.py [ENSEMBLE OUT]``: ``OUT/mI`` for member ``I`` (default: round 24's
``models/imu_denoiser_soles_quint_mirror`` into ``runs/r24/quint_members``)."""
import sys
sys.path.insert(0, ".")
from perception.weights import _write_shipped, load_network
source, out = sys.argv[1:3] if len(sys.argv) == 3 else ("models/imu_denoiser_soles_quint_mirror", "runs/r24/quint_members")
q = load_network(source, "denoiser")
for i, net in enumerate(q.members):
    _write_shipped(f"{out}/m{i}", {"kind": "denoiser", "joints": list(net.input_names), "fps": net.fps,
                   "network": dict(net.config), "state_dict": net.state_dict()},
                   {"kind": "denoiser", "member_of": source, "index": i})
    print(i, dict(net.config))
