"""Show the PNG files a flexarm writer made, as matplotlib figures the gallery collects."""

import matplotlib.pyplot as plt


def show(*paths, width: float = 7.0):
    for path in paths:
        image = plt.imread(str(path))
        h, w = image.shape[:2]
        fig, ax = plt.subplots(figsize=(width, width * h / w))
        ax.imshow(image)
        ax.set_axis_off()
        fig.subplots_adjust(0, 0, 1, 1)
