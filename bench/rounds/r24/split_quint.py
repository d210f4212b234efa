"""Ship each member of models/imu_denoiser_soles_quint_mirror as its own denoiser folder (runs/r24/quint_members/mI)."""
import json
import sys
sys.path.insert(0, ".")
from perception.weights import _write_shipped, load_network
q = load_network("models/imu_denoiser_soles_quint_mirror", "denoiser")
side = json.load(open("models/imu_denoiser_soles_quint_mirror/sidecar.json"))
for i, net in enumerate(q.members):
    _write_shipped(f"runs/r24/quint_members/m{i}", {"kind": "denoiser", "joints": list(net.input_names), "fps": net.fps,
                   "network": dict(net.config), "state_dict": net.state_dict()},
                   {"kind": "denoiser", "member_of": "models/imu_denoiser_soles_quint_mirror", "index": i})
    print(i, dict(net.config))
