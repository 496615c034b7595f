"""Opens a run's GIS exports in QGIS (Debian's python3-qgis, headless) and renders a map.

Usage: /usr/bin/python3 qgis_map.py DEM GPKG DEPTH_TIF OUT_PNG

Loads the DEM (in hypsometric tints), the conduit-depth raster (a colour ramp) and the
GeoPackage's layers (each with the default style stored in the GeoPackage), renders them over the DEM's extent into OUT_PNG (800 px
wide) and prints one JSON line: each layer's CRS, validity, feature count and renderer, and
the map's extent.
"""

import json
import os
import sys

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from qgis.core import (  # noqa: E402
    QgsApplication,
    QgsColorRampShader,
    QgsMapRendererParallelJob,
    QgsMapSettings,
    QgsRasterLayer,
    QgsRasterShader,
    QgsSingleBandPseudoColorRenderer,
    QgsVectorLayer,
)
from qgis.PyQt.QtCore import QSize  # noqa: E402
from qgis.PyQt.QtGui import QColor  # noqa: E402

LAYERS = ["key_points", "segments", "streams", "conduits", "routes", "passages"]


def main(dem_path, gpkg, depth_path, out_png):
    app = QgsApplication([], False)
    app.initQgis()
    dem = QgsRasterLayer(dem_path, "dem")
    depth = QgsRasterLayer(depth_path, "conduit-depth")
    vectors = [QgsVectorLayer(f"{gpkg}|layername={name}", name, "ogr") for name in LAYERS]
    report = {"layers": {}}
    for layer in vectors:
        report["layers"][layer.name()] = {
            "valid": layer.isValid(),
            "crs": layer.crs().authid(),
            "features": layer.featureCount(),
            "renderer": layer.renderer().type() if layer.renderer() else None,
        }
    for layer in (dem, depth):
        report["layers"][layer.name()] = {"valid": layer.isValid(), "crs": layer.crs().authid()}
    style_rasters(dem, depth)
    extent = dem.extent()
    settings = QgsMapSettings()
    # The first layer is drawn on top: the network over the depth raster over the DEM.
    settings.setLayers([layer for layer in vectors if layer.isValid()] + [depth, dem])
    settings.setDestinationCrs(dem.crs())
    settings.setExtent(extent)
    width = 800
    settings.setOutputSize(QSize(width, round(width * extent.height() / extent.width())))
    settings.setBackgroundColor(QColor(255, 255, 255))
    job = QgsMapRendererParallelJob(settings)
    job.start()
    job.waitForFinished()
    image = job.renderedImage()
    report["saved"] = image.save(out_png, "PNG")
    report["size"] = [image.width(), image.height()]
    report["extent"] = [extent.xMinimum(), extent.yMinimum(), extent.xMaximum(), extent.yMaximum()]
    report["map_extent"] = [settings.visibleExtent().xMinimum(), settings.visibleExtent().yMinimum(),
                            settings.visibleExtent().xMaximum(), settings.visibleExtent().yMaximum()]
    print(json.dumps(report), flush=True)
    # QgsApplication's teardown crashes in Debian's 3.22 bindings after an offscreen render
    # (whatever is deleted first); the work is done and reported, so leave without it.
    os._exit(0)


def pseudocolour(layer, stops, opacity):
    """A colour ramp through `stops` [(value, (r, g, b))] on band 1 of `layer`."""
    ramp = QgsColorRampShader(stops[0][0], stops[-1][0])
    ramp.setColorRampType(QgsColorRampShader.Interpolated)
    ramp.setColorRampItemList(
        [QgsColorRampShader.ColorRampItem(v, QColor(*rgb), f"{v:g}") for v, rgb in stops]
    )
    shader = QgsRasterShader()
    shader.setRasterShaderFunction(ramp)
    layer.setRenderer(QgsSingleBandPseudoColorRenderer(layer.dataProvider(), 1, shader))
    layer.setOpacity(opacity)


def style_rasters(dem, depth):
    """The DEM in hypsometric tints, the conduits' depth from yellow (shallow) to purple."""
    stats = dem.dataProvider().bandStatistics(1)
    low, high = stats.minimumValue, stats.maximumValue
    pseudocolour(dem, [(low, (200, 225, 190)), ((low + high) / 2, (235, 225, 190)), (high, (250, 250, 245))], 1.0)
    pseudocolour(depth, [(0.0, (253, 231, 37)), (50.0, (33, 145, 140)), (100.0, (68, 1, 84))], 0.7)


if __name__ == "__main__":
    main(*sys.argv[1:5])
