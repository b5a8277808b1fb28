"""The panel: properties on objects and scenes (properties), operators (operators) and the
sidebar's panels and preferences (panels)."""
