"""An Isomap whose placing of clips (what map_library's tasks run) ends its worker process the first time it runs anywhere (a marker
file records that it did): for the test that a Dask run survives a worker killed mid-run. A
module of its own, so that the workers can import it by name."""
import os

import motionmap


class DyingIsomap(motionmap.Isomap):
    marker = None  # set on the instance: the file whose creation is the one death

    def _placed_clips(self, X, **kwargs):
        if self.marker is not None:
            try:
                fd = os.open(self.marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                pass
            else:
                os.close(fd)
                os._exit(1)  # the worker process dies mid-task, as a crashed machine would
        return super()._placed_clips(X, **kwargs)
