// How far a pointer may move and still be tapping, not dragging: the tap tracker takes a press
// that moved no further as a tap, and the orbit turns nothing until a drag goes past it, so a tap
// that wobbles neither moves the camera nor picks with a camera about to change.

/** CSS pixels a mouse may move while pressed and still tap. */
export const MOUSE_SLOP_PX = 5;
/** CSS pixels a finger or a pen may: a finger wobbles more. */
export const TOUCH_SLOP_PX = 10;

/** The slop of a pointer of this type (PointerEvent.pointerType; a mouse when not said). */
export function slopPx(pointerType: string | undefined): number {
  return (pointerType ?? 'mouse') === 'mouse' ? MOUSE_SLOP_PX : TOUCH_SLOP_PX;
}
