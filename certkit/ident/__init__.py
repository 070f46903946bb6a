"""System identification: LS-SVM, Hammerstein, Wiener and linear (ARX) engines that need no
campaign, and the drop protocol that applies them to a campaign's gear units."""
