"""The env's ``render_mode="human"``: the broadcast view in a pygame window.

pygame (the ``human`` extra, also in ``test``) opens the window on the first frame, where there
is a display; with ``SDL_VIDEODRIVER=dummy`` it draws into memory (CI). The window's close
button is honoured: the window closes and later frames are dropped until the env is reset.
"""

from __future__ import annotations

import logging
import os

import numpy as np

from match.errors import MatchConfigError

log = logging.getLogger(__name__)

WINDOW_TITLE = "robotstadium"


class HumanView:
    """A pygame window that shows RGB frames (uint8, rows top to bottom) at their own size."""

    def __init__(self) -> None:
        self._pygame = None
        self._screen = None
        self.closed_by_user = False

    @staticmethod
    def check_available() -> None:
        """A :class:`MatchConfigError` when pygame cannot be imported."""
        try:
            _pygame()
        except ImportError as error:
            raise MatchConfigError(f"render_mode 'human' needs pygame ({error}); install the 'human' extra or use "
                                   "render_mode='rgb_array'") from None

    def show(self, frame: np.ndarray) -> None:
        """Draw ``frame`` (H x W x 3 uint8) in the window, opening it on the first call."""
        if self.closed_by_user:
            return
        pygame = self._open(frame.shape[1], frame.shape[0])
        for event in pygame.event.get():
            if event.type == pygame.QUIT:
                self.close()
                self.closed_by_user = True
                return
        surface = pygame.surfarray.make_surface(np.ascontiguousarray(frame.transpose(1, 0, 2)))
        self._screen.blit(surface, (0, 0))
        pygame.display.flip()

    def _open(self, width: int, height: int):
        if self._screen is not None:
            return self._pygame
        pygame = _pygame()
        try:
            pygame.display.init()
            self._screen = pygame.display.set_mode((width, height))
        except pygame.error as error:
            raise MatchConfigError(f"render_mode 'human' found no display ({error}); set DISPLAY, or "
                                   "SDL_VIDEODRIVER=dummy to draw off screen, or use render_mode='rgb_array'") from None
        pygame.display.set_caption(WINDOW_TITLE)
        self._pygame = pygame
        log.info("opened the %dx%d window", width, height)
        return pygame

    def reopen(self) -> None:
        """Show frames again after the user closed the window (a new episode)."""
        self.closed_by_user = False

    def close(self) -> None:
        """Close the window; a second call does nothing."""
        if self._pygame is not None:
            self._pygame.display.quit()
        self._pygame = None
        self._screen = None


def _pygame():
    """pygame, imported without its greeting on standard output."""
    os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
    import pygame

    return pygame
