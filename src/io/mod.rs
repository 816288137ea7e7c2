//! Files for people and other tools: NumPy `.npy` arrays, PNG heat maps, grayscale height maps.
