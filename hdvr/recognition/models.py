"""The paper's recognisers: one LSTM per body part for movements, one LSTM for the genre.

- :class:`MovementLSTM`: (B, T, F_e) body-part features -> (B, T, L_e) logits, one per label of part e
  (multi-label: train with binary cross-entropy, threshold sigmoid at 0.5).
- :class:`GenreLSTM`: (B, T, 154) per-frame movement label probabilities of all parts -> (B, G) genre logits from
  the last time step of the last layer (as in the paper), cross-entropy.
"""

from __future__ import annotations

import torch
from torch import nn


class MovementLSTM(nn.Module):
    def __init__(self, in_features: int, num_labels: int, hidden: int = 128, layers: int = 2,
                 bidirectional: bool = True, dropout: float = 0.1):
        super().__init__()
        self.lstm = nn.LSTM(in_features, hidden, layers, batch_first=True, bidirectional=bidirectional,
                            dropout=dropout if layers > 1 else 0.0)
        self.head = nn.Linear(hidden * (2 if bidirectional else 1), num_labels)

    def forward(self, features: torch.Tensor) -> torch.Tensor:
        out, _ = self.lstm(features)
        return self.head(out)


class GenreLSTM(nn.Module):
    def __init__(self, num_labels: int = 154, num_genres: int = 9, hidden: int = 128, layers: int = 2,
                 dropout: float = 0.1):
        super().__init__()
        self.lstm = nn.LSTM(num_labels, hidden, layers, batch_first=True, dropout=dropout if layers > 1 else 0.0)
        self.head = nn.Linear(hidden, num_genres)

    def forward(self, labels: torch.Tensor) -> torch.Tensor:
        out, _ = self.lstm(labels)
        return self.head(out[:, -1])
