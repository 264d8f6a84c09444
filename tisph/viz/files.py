"""The frames' files: PNG written under a temporary name and renamed, the MP4 through
imageio-ffmpeg likewise."""

import os
import warnings

from ..io import OutputError, atomic_path


def write_png(path, img):
    import imageio.v2 as imageio

    try:
        with atomic_path(path) as tmp:
            # zlib level 3: a frame in half the time of the default 6, a fifth larger
            imageio.imwrite(tmp, img, format="PNG", compress_level=3)
    except OSError as e:
        raise OutputError(f"cannot write {path!r}: {e}") from None


class MovieWriter:
    """MP4 through imageio-ffmpeg, written under a temporary name and renamed on close."""

    def __init__(self, path, fps):
        import imageio.v2 as imageio

        self.path = path
        self.tmp = self.tmp_path(path)
        self.writer = None
        try:
            self.writer = imageio.get_writer(
                self.tmp,
                format="FFMPEG",
                fps=fps,
                codec="libx264",
                pixelformat="yuv420p",
                macro_block_size=16,
                ffmpeg_log_level="error",
                quality=7,
            )
        except Exception as e:  # no ffmpeg binary: frames are still written
            warnings.warn(f"MP4 disabled: {e}")

    @staticmethod
    def tmp_path(path):
        d = os.path.dirname(os.path.abspath(path))
        return os.path.join(d, "." + os.path.basename(path) + ".part.mp4")

    def append(self, img):
        if self.writer is not None:
            self.writer.append_data(img)

    def close(self):
        if self.writer is not None:
            self.writer.close()
            self.writer = None
            os.replace(self.tmp, self.path)

    def abort(self):
        if self.writer is not None:
            try:
                self.writer.close()
            finally:
                self.writer = None
                if os.path.exists(self.tmp):
                    os.unlink(self.tmp)
