"""Probe: bench/denoiser_styles.py, with validation's happy style allowed (train or val split; never test)."""
import sys
sys.path.insert(0, "."); sys.path.insert(0, "bench")
import denoiser_styles as ds
from reference_motion.library import expand_clips

def style_clips(library, style):
    split = "val" if style == "happy" else "train"
    return [s for s in expand_clips([f"library:{library}/{split}"]) if f"_{style}_" in s]

ds.style_clips = style_clips
ds.main()
