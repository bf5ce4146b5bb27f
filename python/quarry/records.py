"""Results of quarry.Simulation calls: records of numpy arrays (copies, yours to keep) and the
small tuples of surface and property information."""

from collections import namedtuple


class Record(dict):
    """A dict of numpy arrays whose keys are also attributes (record.position ==
    record["position"]), with metadata attributes of its own."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None


class Particles(Record):
    """Copies of particle arrays in type order (keys: the fields asked for); `epoch` is the
    particles' epoch when copied, `count` their number."""

    def __init__(self, arrays, epoch, count):
        super().__init__(arrays)
        self.epoch = epoch
        self.count = count


class SurfaceLoads(Record):
    """Window-mean loads on a surface: nodal_force (N, (nodes, 3)), pressure (Pa, (elements,)),
    shear_stress (Pa, (elements, 3)), element_force (N, (elements, 3)); `window` (s) is the
    window's length and `time` (s) its end."""

    def __init__(self, arrays, window, time):
        super().__init__(arrays)
        self.window = window
        self.time = time


SurfaceInfo = namedtuple("SurfaceInfo", "node_count element_count triangle_count driver")
PropertyInfo = namedtuple("PropertyInfo", "index name components unit")
