export function sweepPage() { return {}; }
