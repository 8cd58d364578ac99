"""Learned recognition on top of 3D poses (the paper's steps 4 and 5).

- :mod:`hdvr.recognition.features` body-frame features of BODY_25 3D sequences and each part's joints J_e
- :mod:`hdvr.recognition.models`   per-part movement LSTMs (multi-label, BCE) and the genre LSTM (cross-entropy)
- :mod:`hdvr.recognition.train`    movement LSTM training, prediction and checkpoints
- :mod:`hdvr.recognition.genre`    the genre recogniser ``hdvr run`` uses (label resampling, windows, checkpoint)
- :mod:`hdvr.recognition.genre_data` synthetic genre training data, the genre LSTM's training loop
  (:func:`~hdvr.recognition.genre_data.train_genre`) and its scores
"""
